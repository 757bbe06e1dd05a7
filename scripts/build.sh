#!/usr/bin/env bash
# Configures and builds one CMake preset (default: release). Idempotent; incremental.
#   scripts/build.sh [release|debug|asan] [extra cmake --build args...]
set -euo pipefail
cd "$(dirname "$0")/.."
preset="${1:-release}"
shift || true
# ccache (installed by setup.sh) keeps every compiled object by content: a rebuild after a checkout
# elsewhere, or of the same commit by CI, recompiles only what changed. Paths under the repository
# are hashed relative to it, so two checkouts share their objects.
launcher=()
if command -v ccache >/dev/null; then
  launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache -DCMAKE_C_COMPILER_LAUNCHER=ccache)
  export CCACHE_BASEDIR="$PWD" CCACHE_NOHASHDIR=1
fi
if [ ! -f "build/$preset/build.ninja" ]; then
  cmake --preset "$preset" "${launcher[@]}" >/dev/null
fi
cmake --build --preset "$preset" "$@"
