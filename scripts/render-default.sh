#!/usr/bin/env bash
# The main job: installs what is missing, builds, and renders the built-in `default` scene with
# every implemented method. Writes images, visibility EXRs and stats under out/default/ and prints
# the comparison table against the exact reference (also in out/default/summary.md).
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh
scripts/build.sh release --target penumbra_cli
./build/release/penumbra render --scene default --method all --out out/default "$@"
