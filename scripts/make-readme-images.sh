#!/usr/bin/env bash
# Renders the pictures of README.md and docs/ from the bundled scenes and
# styles: each style on the bundled head as styled (frame 1) and after 3 s of
# simulation on a still head (frame 90). Needs a build (scripts/build.sh).
set -euo pipefail
cd "$(dirname "$0")/.."
bin="${LOOSEHAIR:-build/release/app/loosehair}"
[ -x "$bin" ] || { echo "make-readme-images: build first (scripts/build.sh)" >&2; exit 1; }
out=docs/images
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
for style in long-straight bob side-swept swept-back wavy ponytail; do
  camera=three-quarter
  [ "$style" = ponytail ] && camera=side
  "$bin" render data/scenes/hang.json --style "data/styles/$style.json" --frames 90 --size 320x320 \
    --camera "$camera" --out "$work/$style" >/dev/null
  cp "$work/$style/frame_00001.png" "$out/style-$style-styled.png"
  cp "$work/$style/frame_00090.png" "$out/style-$style-3s.png"
  echo "$out/style-$style-styled.png, $out/style-$style-3s.png"
done
# the viewer with its panel, and its styling mode (on a virtual X server)
view="${LOOSEHAIR_VIEW:-$(dirname "$bin")/loosehair-view}"
for script in viewer-panel styling-mode; do
  xvfb-run -a -s "-screen 0 1400x900x24" "$view" --size 1280x720 --script "docs/scripts/$script.json" \
    | grep '^screenshot:'
done
