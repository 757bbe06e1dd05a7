#!/usr/bin/env bash
# The main job: installs what is missing, builds, and renders the built-in `default` scene with
# every implemented method. Writes images, visibility EXRs and stats under out/default/, prints
# the comparison table against the exact reference (also in out/default/summary.md), then writes
# the HTML comparison report out/default/report/index.html and prints its path.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh
scripts/build.sh release --target penumbra_cli
./build/release/penumbra render --scene default --method all --out out/default "$@"
echo
echo "report (open in a browser):"
mkdir -p out/default
if ! ./build/release/penumbra report --scene default --method all --out out/default/report \
  2>out/default/report.log; then
  cat out/default/report.log >&2
  exit 1
fi
