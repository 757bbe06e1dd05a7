#!/usr/bin/env bash
# Configures and builds one CMake preset (default: release). Idempotent; incremental.
#   scripts/build.sh [release|debug|asan] [extra cmake --build args...]
set -euo pipefail
cd "$(dirname "$0")/.."
preset="${1:-release}"
shift || true
if [ ! -f "build/$preset/build.ninja" ]; then
  cmake --preset "$preset" >/dev/null
fi
cmake --build --preset "$preset" "$@"
