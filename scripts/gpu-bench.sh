#!/usr/bin/env bash
# The GPU backend in one run: build, check (the Vulkan tests), time. GPU stage times come from
# Vulkan timestamp queries (stats.json "gpu_*"), wall times from the host ("wall_*" and the
# method total); the CPU methods run on the same frames for the ratio.
#   scripts/gpu-bench.sh [out-dir]      (PENUMBRA_VK_DEVICE picks the device)
set -euo pipefail
cd "$(dirname "$0")/.."
out="${1:-build/gpu-bench}"
scripts/setup.sh
scripts/build.sh release --target penumbra_cli test_vulkan_compute test_vulkan_depth_maps test_vulkan_gears
for t in compute depth_maps gears; do build/release/tests/test_vulkan_$t --gtest_brief=1; done
scripts/fetch-models.sh >/dev/null
bin=build/release/penumbra
mkdir -p "$out"
for scene in bunny dragon; do
  for backend in vulkan cpu; do
    # gears at k = 16 (16×16 samples) and the depth-map methods, 1024², the paper's setting.
    "$bin" render --scene "$scene" --size 1024x1024 --samples 16 --backend "$backend" \
      --method gears --method shadow_map --method pcss --out "$out/$scene-$backend" >/dev/null
  done
done
python3 - "$out" <<'PY'
import json, pathlib, sys
out = pathlib.Path(sys.argv[1])
print("| scene | method | cpu total ms | vulkan total ms | ratio | vulkan GPU stages (ms, timestamps) | device |")
print("|---|---|---|---|---|---|---|")
for scene in ("bunny", "dragon"):
    for method in ("gears", "shadow_map", "pcss"):
        g = json.loads((out / f"{scene}-vulkan" / method / "stats.json").read_text())
        c = json.loads((out / f"{scene}-cpu" / method / "stats.json").read_text())
        gt, ct = g["times_ms"], c["times_ms"]
        stages = ", ".join(f"{k[4:]} {v:.2f}" for k, v in gt.items() if k.startswith("gpu_"))
        print(f"| {scene} | {method} | {ct['total']:.1f} | {gt['total']:.1f} | "
              f"{ct['total'] / gt['total']:.1f}× | {stages} | {g['device']} |")
PY
