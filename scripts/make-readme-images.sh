#!/usr/bin/env bash
# Renders the pictures of README.md and docs/ from the bundled scenes and
# styles: each style on the bundled head as styled (frame 1) and after 3 s of
# simulation on a still head (frame 90) from four sides. Needs a build (scripts/build.sh).
set -euo pipefail
cd "$(dirname "$0")/.."
bin="${LOOSEHAIR:-build/release/app/loosehair}"
[ -x "$bin" ] || { echo "make-readme-images: build first (scripts/build.sh)" >&2; exit 1; }
out=docs/images
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
# and after 3 s from the front, the side, the back and three-quarters
for style in long-straight bob side-swept swept-back wavy ponytail; do
  for camera in three-quarter front side back; do
    "$bin" render data/scenes/hang.json --style "data/styles/$style.json" --frames 90 --size 320x320 \
      --camera "$camera" --out "$work/$style-$camera" >/dev/null
    cp "$work/$style-$camera/frame_00090.png" "$out/style-$style-3s-$camera.png"
  done
  cp "$work/$style-three-quarter/frame_00001.png" "$out/style-$style-styled.png"
  echo "$out/style-$style-styled.png, $out/style-$style-3s-{three-quarter,front,side,back}.png"
done
# the same frame (hang.json after 3 s) as billboards and as strands, front
# and side, with and without shadows, and with Marschner shading
for view in front side; do
  for hair in billboards strands; do
    "$bin" render data/scenes/hang.json --frames 90 --size 320x240 --camera "$view" --hair "$hair" \
      --out "$work/$hair-$view" >/dev/null
    cp "$work/$hair-$view/frame_00090.png" "$out/hang-$hair-$view.png"
    echo "$out/hang-$hair-$view.png"
  done
done
"$bin" render data/scenes/hang.json --frames 90 --size 320x240 --camera front --no-shadows --out "$work/noshadow" >/dev/null
cp "$work/noshadow/frame_00090.png" "$out/hang-strands-front-no-shadows.png"
"$bin" render data/scenes/hang.json --frames 90 --size 320x240 --camera front --hair billboards --no-shadows \
  --out "$work/noshadow-bb" >/dev/null
cp "$work/noshadow-bb/frame_00090.png" "$out/hang-billboards-front-no-shadows.png"
"$bin" render data/scenes/hang.json --frames 90 --size 320x240 --camera three-quarter --shading marschner \
  --out "$work/marschner" >/dev/null
cp "$work/marschner/frame_00090.png" "$out/hang-strands-marschner.png"
"$bin" render data/scenes/hang.json --frames 90 --size 320x240 --camera three-quarter --out "$work/kk" >/dev/null
cp "$work/kk/frame_00090.png" "$out/hang-strands-kajiya-kay.png"
echo "$out/hang-strands-front-no-shadows.png, $out/hang-strands-marschner.png"
# the viewer with its panel, and its styling mode (on a virtual X server)
view="${LOOSEHAIR_VIEW:-$(dirname "$bin")/loosehair-view}"
for script in viewer-panel styling-mode; do
  xvfb-run -a -s "-screen 0 1400x900x24" "$view" --size 1280x720 --script "docs/scripts/$script.json" \
    | grep '^screenshot:'
done
