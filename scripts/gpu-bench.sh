#!/usr/bin/env bash
# The GPU backend in one run: build, check, time — for a real GPU (headless Vulkan; the loader
# finds the vendor's ICD, e.g. NVIDIA's on an H200) as for lavapipe.
#   1. build the release CLI, the Vulkan tests and bench/bench_vulkan;
#   2. check: the Vulkan tests (masks, maps and counts against the CPU methods on the test scenes),
#      then on every benchmarked frame the Vulkan result against the CPU method's: per-sample
#      masks for gears and dcs, per-pixel visibility for wedges, wedge_blend, ssm, shadow_map, pcss,
#      silhouette_map and shadow_volume (fails the run past the bounds of docs/gpu.md);
#   3. time: GPU stage times from timestamp queries and host wall times (Vulkan), stage wall times
#      (CPU), printed as the GEARS paper's Tables 1, 2 and 5 [Wang 2014 §4.3], a method × scene
#      table (every Vulkan method against its CPU twin, the CPU raytrace and the Vulkan gears), the
#      paper's scene classes (nest, garden) and its Table 10 (the animated built-ins frame by frame,
#      geometry prepared again per frame).
#      JSON in <out-dir>/bench.json, the tables in <out-dir>/tables.md.
#   scripts/gpu-bench.sh [out-dir]
# PENUMBRA_VK_DEVICE picks the device (index or name substring). PENUMBRA_GPU_BENCH=full runs the
# paper's sizes (Table 1: 512², 1024², 1280²; Table 2: 1024²; Table 5: 512²; classes and Table 10:
# 1024², 16 frames), =quick the sizes a CPU Vulkan device manages (128², 256²; 256²; 128²; 64²,
# 2 frames); default: quick on lavapipe, else full.
set -euo pipefail
cd "$(dirname "$0")/.."
out="${1:-build/gpu-bench}"
mkdir -p "$out"
if ! command -v glslc >/dev/null || [ ! -f /usr/include/vulkan/vulkan.h ]; then scripts/setup.sh; fi
scripts/build.sh release --target penumbra_cli bench_vulkan test_vulkan_compute \
  test_vulkan_depth_maps test_vulkan_gears test_vulkan_dcs test_vulkan_wedges test_vulkan_ssm \
  test_vulkan_shadow_volume test_vulkan_silhouette_map test_vulkan_meshes
for t in compute depth_maps gears dcs wedges ssm shadow_volume silhouette_map meshes; do build/release/tests/test_vulkan_$t --gtest_brief=1; done
# bunny and dragon (scripts/fetch-models.sh); without them (an offline machine) the built-in spheres.
scenes="bunny|dragon"
models="${PENUMBRA_MODELS:-${XDG_CACHE_HOME:-$HOME/.cache}/penumbra/models}"
[ -f "$models/bunny00.off" ] || scripts/fetch-models.sh >/dev/null || scenes=spheres

device=$(build/release/penumbra render --scene quad --size 16x16 --method shadow_map --backend vulkan \
  --out "$out/probe" 2>&1 >/dev/null | sed -n 's/^vulkan device: //p')
mode="${PENUMBRA_GPU_BENCH:-$([[ "$device" == llvmpipe* ]] && echo quick || echo full)}"
if [ "$mode" = full ]; then t1="512|1024|1280" t2=1024 t5=512 r=1024 c=1024 q=1024
else t1="128|256" t2=256 t5=128 r=256 c=64 q=64; fi
echo "device: $device; mode: $mode; load: $(cut -d' ' -f1-3 /proc/loadavg)"
filter="^BM_(Cpu|Vulkan)/(gears_($scenes)/($t1|$t2)/16|gears_($scenes)/$t5/(4|8|16|32)"
filter+="|(dcs|wedges|wedge_blend|ssm|raytrace|shadow_map|pcss|shadow_volume|silhouette_map)_($scenes)/$r/16"
filter+="|(gears|raytrace)_(nest|garden)/$c/16)/|^BM_RadixSort/|^BM_Sequence/[a-z_]+/$q/"
build/release/bench/bench_vulkan --benchmark_filter="$filter" --benchmark_out="$out/bench.json" \
  --benchmark_out_format=json >/dev/null

python3 - "$out" "$t1" "$t2" "$t5" "$r" "$device" "$scenes" "$c" "$q" <<'PY' | tee "$out/tables.md"
import json, pathlib, re, sys
out, t1, t2, t5, r, device, scene_list, c_size, q_size = sys.argv[1:]
runs, sorts, sequences = {}, [], []
for b in json.loads((pathlib.Path(out) / "bench.json").read_text())["benchmarks"]:
    if b["name"].startswith("BM_RadixSort/") and not b.get("error_occurred"):
        sorts.append(b)
    m = re.match(r"BM_Sequence/(\w+)/(\d+)/(\d+)/", b["name"])
    if m and not b.get("error_occurred"):
        sequences.append((m[1], int(m[2]), int(m[3]), b))
        continue
    m = re.match(r"BM_(Cpu|Vulkan)/(\w+?)_(bunny|dragon|spheres|nest|garden)/(\d+)/(\d+)/", b["name"])
    if m and not b.get("error_occurred"):
        runs[(m[1], m[2], m[3], int(m[4]), int(m[5]))] = b
scenes = scene_list.split("|")
def get(backend, method, scene, size, k):
    return runs.get((backend, method, scene, size, k))
def ms(b):
    return f"{b['real_time']:.1f}" if b else "–"
failed = []
def check(method, scene, size, k):
    g = get("Vulkan", method, scene, size, k)
    if not g:
        return "–"
    if method in ("gears", "dcs"):  # sample-exact: per-sample masks
        frac = g["differ_samples"] / max(1.0, g["active_pixels"] * k * k)
        ok = frac <= 1e-3  # ≥ 99.9 % of (pixel, sample) pairs equal
        text = f"{g['differ_samples']:.0f} samples"
    else:
        frac = g["differ_pixels"] / max(1.0, g["active_pixels"])
        ok = frac <= (1e-3 if method in ("shadow_volume", "ssm", "wedges", "wedge_blend",
                                         "silhouette_map") else 5e-3)
        text = f"{g['differ_pixels']:.0f} px"
    if not ok:
        failed.append(f"{method} {scene} {size}² k={k}: {text}")
    return text + ("" if ok else " FAIL")

print(f"Device: {device}. Vulkan: wall ms per frame (host, around upload, GPU work and readback) "
      "and the sum of the GPU stage times (timestamps); CPU: wall ms per frame of the CPU method on "
      "the same frame. Check: CPU vs Vulkan differences on that frame.\n")
print("Table 1 (gears, k = 16, default grids: Vulkan size / 2 cells per side up to 255, CPU size / 8): ms per frame vs output size\n")
print("| scene | size | Vulkan wall ms | Vulkan GPU ms | CPU ms | CPU / Vulkan | check |")
print("|---|---|---|---|---|---|---|")
for scene in scenes:
    for size in map(int, t1.split("|")):
        g, c = get("Vulkan", "gears", scene, size, 16), get("Cpu", "gears", scene, size, 16)
        gpu = sum(v for k, v in g.items() if k.startswith("gpu_")) if g else 0.0
        ratio = f"{c['real_time'] / g['real_time']:.2f}×" if g and c else "–"
        print(f"| {scene} | {size}² | {ms(g)} | {gpu:.1f} | {ms(c)} | {ratio} | "
              f"{check('gears', scene, size, 16)} |")

steps = [("project pixels", ["gpu_pixel_cells"], ["project_pixels"]),
         ("prefix sum of cell counts", ["gpu_triangle_count", "gpu_prefix_sum"], ["count_prefix_sum"]),
         ("relate triangles to cells", ["gpu_pair_write"], ["write_pairs"]),
         ("sort pairs by cell", ["gpu_radix_sort", "gpu_cell_ranges"], ["sort_pairs"]),
         ("bitmask rasterization", ["gpu_rasterize"], ["bitmask_rasterization"])]
print(f"\nTable 2 (gears, {t2}², k = 16): ms per step (Vulkan: GPU timestamps; CPU: stage wall times)\n")
print("| scene | backend | " + " | ".join(s[0] for s in steps) + " |")
print("|---|---|" + "---|" * len(steps))
for scene in scenes:
    for backend, col in (("Vulkan", 1), ("Cpu", 2)):
        b = get(backend, "gears", scene, int(t2), 16)
        cells = [f"{sum(b.get(k, 0.0) for k in s[col]):.2f}" if b else "–" for s in steps]
        print(f"| {scene} | {backend.lower()} | " + " | ".join(cells) + " |")

print(f"\nTable 5 (gears, {t5}², default grids): ms per frame vs bitmask resolution k×k (Vulkan / CPU)\n")
print("| scene | " + " | ".join(f"{k}×{k}" for k in (4, 8, 16, 32)) + " |")
print("|---|" + "---|" * 4)
for scene in scenes:
    cells = []
    for k in (4, 8, 16, 32):
        g, c = get("Vulkan", "gears", scene, int(t5), k), get("Cpu", "gears", scene, int(t5), k)
        cells.append(f"{ms(g)} / {ms(c)} ({check('gears', scene, int(t5), k)})")
    print(f"| {scene} | " + " | ".join(cells) + " |")

print(f"\nRaster methods ({r}²): ms per frame, Vulkan GPU stages from timestamps\n")
print("| method | scene | Vulkan wall ms | GPU stages (ms) | CPU ms | check |")
print("|---|---|---|---|---|---|")
for method in ("shadow_map", "pcss", "silhouette_map", "shadow_volume"):
    for scene in scenes:
        g, c = get("Vulkan", method, scene, int(r), 16), get("Cpu", method, scene, int(r), 16)
        stages = ", ".join(f"{k[4:]} {v:.2f}" for k, v in sorted(g.items())
                           if k.startswith("gpu_")) if g else "–"
        print(f"| {method} | {scene} | {ms(g)} | {stages} | {ms(c)} | "
              f"{check(method, scene, int(r), 16)} |")
print(f"\nEvery Vulkan method ({r}², k = 16): ms per frame; vs raytrace = CPU raytrace ms / Vulkan "
      "ms, vs gears = Vulkan gears ms / Vulkan ms (above 1: faster than the GPU gears)\n")
print("| method | scene | Vulkan wall ms | CPU ms | CPU / Vulkan | vs raytrace | vs gears | check |")
print("|---|---|---|---|---|---|---|---|")
for method in ("gears", "dcs", "wedges", "wedge_blend", "ssm", "shadow_map", "pcss",
               "silhouette_map", "shadow_volume"):
    for scene in scenes:
        g, c = get("Vulkan", method, scene, int(r), 16), get("Cpu", method, scene, int(r), 16)
        rt, gg = get("Cpu", "raytrace", scene, int(r), 16), get("Vulkan", "gears", scene, int(r), 16)
        def ratio(a, b):
            return f"{a['real_time'] / b['real_time']:.2f}×" if a and b else "–"
        print(f"| {method} | {scene} | {ms(g)} | {ms(c)} | {ratio(c, g)} | {ratio(rt, g)} | "
              f"{ratio(gg, g)} | {check(method, scene, int(r), 16)} |")
print(f"\nThe GEARS paper's scene classes (gears, {c_size}², k = 16): ms per frame; vs raytrace = CPU "
      "raytrace ms / Vulkan gears ms\n")
print("| scene | Vulkan wall ms | CPU gears ms | CPU raytrace ms | vs raytrace | check |")
print("|---|---|---|---|---|---|")
for scene in ("nest", "garden"):
    g, c, rt = (get("Vulkan", "gears", scene, int(c_size), 16), get("Cpu", "gears", scene, int(c_size), 16),
                get("Cpu", "raytrace", scene, int(c_size), 16))
    ratio = f"{rt['real_time'] / g['real_time']:.2f}×" if g and rt else "–"
    print(f"| {scene} | {ms(g)} | {ms(c)} | {ms(rt)} | {ratio} | {check('gears', scene, int(c_size), 16)} |")

print("\nTable 10 (dynamic scenes, gears, k = 16): ms per frame over frames 0 … n−1, each method "
      "prepared again on every frame whose geometry moves (inside its time; the CPU raytrace "
      "rebuilds its BVH there); check: samples where the Vulkan and CPU gears masks differ, all frames\n")
print("| scene | moves | size | frames | Vulkan gears ms | CPU gears ms | CPU raytrace ms | vs raytrace | check |")
print("|---|---|---|---|---|---|---|---|---|")
for name, size, frames, b in sequences:
    if size != int(q_size):
        continue
    frac = b["differ_samples"] / max(1.0, b["active_pixels"] * 256)
    ok = frac <= 1e-3
    if not ok:
        failed.append(f"sequence {name} {size}²: {b['differ_samples']:.0f} samples")
    moves = "geometry" if b["moves_geometry"] else "light"
    print(f"| {name} | {moves} | {size}² | {frames} | {b['vulkan_gears_ms']:.1f} | {b['cpu_gears_ms']:.1f} | "
          f"{b['raytrace_ms']:.1f} | {b['raytrace_ms'] / b['vulkan_gears_ms']:.2f}× | "
          f"{b['differ_samples']:.0f} samples{'' if ok else ' FAIL'} |")

print("\nRadix sort of the (cell, triangle) pairs alone, 2^20 pairs: GPU ms (timestamps) per block ranking\n")
print("| ranking | key bits | GPU ms |")
print("|---|---|---|")
for b in sorts:
    ranking, _, bits = b["name"].split("/")[1:4]
    print(f"| {ranking} | {bits} | {b['gpu_ms']:.1f} |")
if failed:
    print("\nCHECK FAILED: " + "; ".join(failed))
    sys.exit(1)
PY
