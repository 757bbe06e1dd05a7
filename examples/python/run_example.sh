#!/usr/bin/env bash
# Runs one example with small settings and checks that it wrote its PNG (ctest: python.example.*).
# Exit 77 (skipped) when matplotlib is missing. Usage: run_example.sh PYTHON SCRIPT OUT
set -euo pipefail
python=$1 script=$2 out=$3
"$python" -c "import matplotlib" 2>/dev/null || { echo "matplotlib missing: skipped"; exit 77; }
rm -rf "$out"
case "$(basename "$script")" in
  light_size_sweep.py) "$python" "$script" --size 64x48 --samples 4 --scales 0.5,1,2 --out "$out" ;;
  *) "$python" "$script" --size 80x60 --out "$out" ;;
esac
png=$(find "$out" -name '*.png' | head -1)
[ -n "$png" ] && [ "$(head -c 4 "$png" | od -An -c | tr -d ' ')" = "211PNG" ] || {
  echo "no PNG written under $out"; exit 1; }
