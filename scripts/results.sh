#!/usr/bin/env bash
# Regenerates the method × scene tables of docs/results.md: every method on every scene, error
# against `exact` and speed against `raytrace` measured in the same run. Prints Markdown.
#   scripts/results.sh [WxH] [K] [scenes...]     (defaults: 512x512, 16, all scenes present)
set -euo pipefail
cd "$(dirname "$0")/.."
size="${1:-512x512}"
k="${2:-16}"
shift 2 || shift $# || true
scenes=("$@")
[ ${#scenes[@]} -gt 0 ] || scenes=(quad spheres fence default bunny dragon)
mkdir -p out/results
bin=./build/release/penumbra
[ -x "$bin" ] || scripts/build.sh release --target penumbra_cli >&2
echo "Machine: $(nproc) cores, $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ *//'); $(date -u +%Y-%m-%d)"
for scene in "${scenes[@]}"; do
  out="out/results/$scene-$size-k$k"
  cmd="$bin render --scene $scene --method all --size $size --samples $k --out $out"
  if ! PENUMBRA_NO_PROGRESS=1 $cmd >/dev/null 2>"$out.log"; then
    echo >&2 "results: $scene skipped: $(tail -1 "$out.log")"
    continue
  fi
  echo
  echo "### $scene, $size, ${k}×$k light samples"
  echo
  echo '```sh'
  echo "$cmd"
  echo '```'
  echo
  cat "$out/summary.md"
done
