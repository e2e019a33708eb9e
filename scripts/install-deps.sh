#!/usr/bin/env bash
# Installs every Debian package loosehair needs to build, test, benchmark and render.
# Safe to run any number of times: apt-get skips what is already installed.
set -euo pipefail

packages=(
  build-essential cmake pkg-config git
  libglm-dev            # vector maths (sim, render)
  libeigen3-dev         # sparse linear algebra (harmonic map)
  nlohmann-json3-dev    # scene files
  libopenmesh-dev       # mesh loading (OBJ, PLY, OFF, STL)
  libtinygltf-dev       # glTF / GLB loading
  libopenvdb-dev        # signed-distance bake of body meshes
  libboost-dev          # headers OpenVDB includes (not a dependency of its -dev package)
  libstb-dev            # PNG / image reading and writing
  libglfw3-dev libgl-dev  # interactive viewer window
  libimgui-dev          # the viewer's panel (Dear ImGui with its GLFW and OpenGL 3 backends)
  libosmesa6-dev        # headless OpenGL (software, no X server)
  libegl-dev            # headless OpenGL on a GPU where there is one (EGL, no X server)
  libegl-mesa0          # Mesa's EGL: its surfaceless platform on llvmpipe elsewhere
  libgtest-dev libgmock-dev  # tests
  libbenchmark-dev      # benchmarks
  ffmpeg                # video encoding of rendered frames
  xvfb xauth            # running the windowed viewer without a display
  python3-open3d assimp-utils  # independent readers of strand files in the tests
  libgl1-mesa-dri libglx-mesa0  # OpenGL in a window on the software renderer
)

SUDO=""
if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi

missing=()
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done

if [ ${#missing[@]} -eq 0 ]; then
  echo "install-deps: all ${#packages[@]} packages already installed"
  exit 0
fi

echo "install-deps: installing ${missing[*]}"
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
$SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
echo "install-deps: done"
