#!/usr/bin/env bash
# Installs what is missing, builds and runs the whole test suite twice: the release build, then the
# ASan+UBSan build. `scripts/test.sh release` (or `asan`) runs just one of them.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh
presets=("${@:-release asan}")
for preset in ${presets[*]}; do
  echo "== $preset: build"
  scripts/build.sh "$preset"
  echo "== $preset: test"
  PENUMBRA_NO_PROGRESS=1 ctest --preset "$preset"
done
