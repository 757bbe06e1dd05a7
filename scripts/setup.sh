#!/usr/bin/env bash
# Installs every Debian package Penumbra's build, tests and benchmarks need.
# Idempotent and non-interactive; returns quickly when everything is present.
set -euo pipefail

PACKAGES=(
  build-essential cmake ninja-build pkg-config clang-format
  ccache  # scripts/build.sh and scripts/fuzz.sh: rebuilds compile only what changed
  libhwy-dev  # Highway: runtime SIMD dispatch of the hot kernels
  libembree-dev libtbb-dev libassimp-dev libglm-dev libstb-dev
  libcli11-dev nlohmann-json3-dev libopenexr-dev
  zlib1g-dev  # the PNG writer's deflate
  libgtest-dev libgmock-dev libbenchmark-dev libpolyclipping-dev
  hyperfine  # whole-process timings in docs/results.md
  ffmpeg  # `render --frames`: beauty.mp4 and compare.mp4 (H.264); without it only the frames
  # The Vulkan backend: loader + headers, the GLSL compiler, lavapipe (a CPU Vulkan 1.3 device,
  # so the GPU tests run everywhere) and the validation layer.
  libvulkan-dev glslc mesa-vulkan-drivers vulkan-validationlayers
  clang libclang-rt-14-dev valgrind  # scripts/fuzz.sh: libFuzzer with ASan+UBSan, valgrind replay
  chromium  # the report's browser test (tests/report/browser_test.sh)
  # `penumbra view`: GLFW + Dear ImGui (its static library carries the GLFW and OpenGL 3 back
  # ends); its tests run under Xvfb with Mesa's software OpenGL.
  libglfw3-dev libimgui-dev xvfb xauth libgl1-mesa-dri
  # The Python module (docs/api.md), its tests and examples: for /usr/bin/python3.
  pybind11-dev python3-dev python3-numpy python3-pytest python3-matplotlib
)

missing=()
for pkg in "${PACKAGES[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$pkg" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$pkg")
  fi
done

if [ ${#missing[@]} -eq 0 ]; then
  exit 0
fi

echo "setup: installing ${missing[*]}"
SUDO=""
if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
$SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
echo "setup: done"
