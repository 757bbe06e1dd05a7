// Google Benchmark: the Vulkan backend against the CPU methods on the same cached frames, in one
// run (scripts/gpu-bench.sh formats the paper's tables from its JSON).
//   ./build/release/bench/bench_vulkan --benchmark_filter='gears_bunny/1024/16$'
// Args: {image size, k (k×k grid samples)}. BM_Cpu/<method>_<scene>: the CPU method, counters =
// its stage times (ms per frame). BM_Vulkan/<method>_<scene>: the Vulkan method after one untimed
// run (pipelines are compiled on first use), counters = the GPU stage times from timestamp queries
// (gpu_*) and the host wall times around them (wall_*), plus the check against the CPU method on
// the same frame: differ_pixels (|ΔV| > 1e-6) among active_pixels, max_abs_dv and, for gears,
// differ_samples (per-sample masks) for the sample-exact methods (gears, dcs). BM_Cpu/raytrace_*
// times the reference every method's table row is compared with. Skipped without a Vulkan device
// or a fetched model.
// BM_RadixSort/<ranking>: the GEARS pair sort alone (gpu/sort.hpp), its two block rankings on the
// same keys — subgroup ballots (linear in the block size) and byte compares (quadratic, the
// fallback of devices without ballots); Args {log2 of the pair count, key bits}, counter gpu_ms.
#include <benchmark/benchmark.h>

#ifdef PENUMBRA_HAVE_VULKAN

#include <bit>
#include <cmath>
#include <deque>
#include <map>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "bench_fixture.hpp"
#include "penumbra/gpu/backend.hpp"
#include "penumbra/gpu/sort.hpp"
#include "penumbra/pipeline/sequence.hpp"
#include "penumbra/render/receivers.hpp"

namespace penumbra {
namespace {

gpu::Backend* backend() {
  static const std::unique_ptr<gpu::Backend> b = []() -> std::unique_ptr<gpu::Backend> {
    if (!gpu::vulkan_available()) return nullptr;
    return std::make_unique<gpu::Backend>();
  }();
  return b.get();
}

const bench::Fixture* frame_or_skip(benchmark::State& state, const std::string& scene) {
  const bench::Fixture* f = bench::cached_frame(scene, static_cast<int>(state.range(0)),
                                                static_cast<int>(state.range(1)));
  if (!f) state.SkipWithError(bench::kNotFetched);
  return f;
}

/// Times `info` on the frame; counters = the per-frame mean of every stage time.
void time_runs(benchmark::State& state, const Frame& frame, const MethodInfo& info,
               const MethodOptions& opts) {
  std::map<std::string, double> sums;
  for (auto _ : state) {
    const MethodResult r = frame.run(info, opts, false);
    for (const auto& [stage, ms] : r.per_light[0].times.stages()) sums[stage] += ms;
    benchmark::DoNotOptimize(r.per_light[0].lit.data());
  }
  for (const auto& [stage, ms] : sums)
    state.counters[stage] = ms / static_cast<double>(state.iterations());
}

void BM_Cpu(benchmark::State& state, const std::string& method, const std::string& scene) {
  const bench::Fixture* f = frame_or_skip(state, scene);
  if (!f) return;
  const MethodInfo& info = MethodRegistry::builtin().get(method);
  time_runs(state, *f->frame, info, resolve_options(info, {}));
}

/// The GPU result against the CPU method's on the same frame (one run each, masks for gears).
void check(benchmark::State& state, const bench::Fixture& f, const MethodInfo& cpu_info,
           const MethodInfo& gpu_info, const MethodOptions& opts) {
  const bool masks = cpu_info.sample_exact;  // gears, dcs: per-sample masks
  const MethodResult cpu = f.frame->run(cpu_info, opts, masks);
  const MethodResult gpu = f.frame->run(gpu_info, opts, masks);
  const Visibility &c = cpu.per_light[0], &g = gpu.per_light[0];
  double active = 0.0, differ = 0.0, max_abs = 0.0, differ_samples = 0.0;
  const Image<uint8_t>& receivers = f.frame->receivers(0);
  for (size_t i = 0; i < receivers.size(); ++i) {
    if (receivers[i] != kActive) continue;
    ++active;
    const double d = std::abs(static_cast<double>(c.lit[i]) - g.lit[i]);
    differ += d > 1e-6;
    max_abs = std::max(max_abs, d);
    if (masks && c.masks && g.masks)
      for (int w = 0; w < c.masks->words_per_pixel(); ++w)
        differ_samples += std::popcount(c.masks->pixel(i)[w] ^ g.masks->pixel(i)[w]);
  }
  state.counters["active_pixels"] = active;
  state.counters["differ_pixels"] = differ;
  state.counters["max_abs_dv"] = max_abs;
  if (masks) state.counters["differ_samples"] = differ_samples;
}

void BM_Vulkan(benchmark::State& state, const std::string& method, const std::string& scene) {
  gpu::Backend* b = backend();
  if (!b) {
    state.SkipWithError("no Vulkan device");
    return;
  }
  const bench::Fixture* f = frame_or_skip(state, scene);
  if (!f) return;
  const MethodInfo& cpu_info = MethodRegistry::builtin().get(method);
  const MethodInfo info = b->vulkan_method(cpu_info);
  const MethodOptions opts = resolve_options(info, {});
  f->frame->run(info, opts, false);  // compiles the pipelines
  time_runs(state, *f->frame, info, opts);
  check(state, *f, cpu_info, info, opts);
  state.SetLabel(b->context().device_name());
}

/// {size, k}: the paper's output sizes at k = 16 (Table 1, and the stage breakdown of Table 2)
/// with the small sizes a CPU Vulkan device (lavapipe) manages, and the bitmask sweep (Table 5).
void gears_args(benchmark::internal::Benchmark* b) {
  for (int size : {128, 256, 512, 1024, 1280}) b->Args({size, 16});
  for (int size : {128, 512})
    for (int k : {4, 8, 32}) b->Args({size, k});
  b->Unit(benchmark::kMillisecond)->UseRealTime()->MinTime(0.3);
}
void raster_args(benchmark::internal::Benchmark* b) {
  for (int size : {128, 256, 1024}) b->Args({size, 16});
  b->Unit(benchmark::kMillisecond)->UseRealTime()->MinTime(0.3);
}

/// The scene classes of the GEARS paper (Bird Nest, Garden): gears and the CPU raytrace only.
void class_args(benchmark::internal::Benchmark* b) {
  for (int size : {64, 1024}) b->Args({size, 16});
  b->Unit(benchmark::kMillisecond)->UseRealTime()->MinTime(0.3);
}

/// Dynamic scenes [Wang 2014 Table 10]: frames 0 … frames−1 of an animated built-in posed one after
/// the other (`render --frames`), each method prepared again on every frame whose geometry moves,
/// inside its time; the CPU raytrace rebuilds its BVH on those frames. One pass over the frames;
/// counters: ms per frame of the Vulkan gears, the CPU gears and the CPU raytrace (with their
/// preparation), and the samples where the two gears' masks differ over every frame.
void BM_Sequence(benchmark::State& state, const std::string& scene_name) {
  gpu::Backend* b = backend();
  if (!b) {
    state.SkipWithError("no Vulkan device");
    return;
  }
  Scene scene = make_builtin_scene(scene_name);
  scene.camera.width = scene.camera.height = static_cast<int>(state.range(0));
  const int frames = static_cast<int>(state.range(1));
  const MethodRegistry& registry = MethodRegistry::builtin();
  const MethodInfo& cpu_gears = registry.get("gears");
  const MethodInfo& raytrace = registry.get("raytrace");
  const MethodInfo vk_gears = b->vulkan_method(cpu_gears);
  std::vector<SequenceMethod> methods = {{&vk_gears, resolve_options(vk_gears, {})},
                                         {&cpu_gears, resolve_options(cpu_gears, {})},
                                         {&raytrace, resolve_options(raytrace, {})}};
  LightSampleSpec spec;
  spec.pattern = SamplePattern::grid;
  spec.k = 16;
  double ms[3] = {0.0, 0.0, 0.0}, differ = 0.0, active = 0.0;
  {
    SequenceRenderer warm_up(scene, methods, spec, false);
    warm_up.render(0);  // compiles the pipelines; not timed
  }
  for (auto _ : state) {
    SequenceRenderer renderer(scene, methods, spec, true);
    for (int f = 0; f < frames; ++f) {
      const SequenceFrame frame = renderer.render(f);
      for (int m = 0; m < 3; ++m) ms[m] += frame.results[m].total_ms;
      const Visibility &g = frame.results[0].per_light[0], &c = frame.results[1].per_light[0];
      const Image<uint8_t>& receivers = frame.frame->receivers(0);
      for (size_t i = 0; i < receivers.size(); ++i) {
        if (receivers[i] != kActive) continue;
        ++active;
        for (int w = 0; w < c.masks->words_per_pixel(); ++w)
          differ += std::popcount(c.masks->pixel(i)[w] ^ g.masks->pixel(i)[w]);
      }
    }
  }
  const double per_frame = static_cast<double>(state.iterations()) * frames;
  state.counters["vulkan_gears_ms"] = ms[0] / per_frame;
  state.counters["cpu_gears_ms"] = ms[1] / per_frame;
  state.counters["raytrace_ms"] = ms[2] / per_frame;
  state.counters["differ_samples"] = differ;
  state.counters["active_pixels"] = active;
  state.counters["moves_geometry"] = scene.animation.moves_geometry() ? 1.0 : 0.0;
  state.SetLabel(b->context().device_name());
}
/// {size, frames}: the lavapipe sizes and the paper's.
void sequence_args(benchmark::internal::Benchmark* b) {
  b->Args({64, 2})->Args({1024, 16});
  b->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(1);
}

void BM_RadixSort(benchmark::State& state, gpu::RadixRanking ranking) {
  gpu::Backend* b = backend();
  if (!b) {
    state.SkipWithError("no Vulkan device");
    return;
  }
  gpu::VulkanContext& vk = b->context();
  if (ranking == gpu::RadixRanking::ballot && !vk.has_subgroup_ballot()) {
    state.SkipWithError("no subgroup ballots");
    return;
  }
  const uint32_t n = 1u << state.range(0);
  const int bits = static_cast<int>(state.range(1));
  std::mt19937 rng(7);
  std::vector<uint32_t> keys(n), vals(n);
  for (uint32_t i = 0; i < n; ++i) keys[i] = rng() & ((1u << bits) - 1u), vals[i] = i;
  const gpu::Buffer k = vk.upload(keys), v = vk.upload(vals);
  const gpu::Buffer kt(vk, n * 4, gpu::Memory::device), vt(vk, n * 4, gpu::Memory::device);
  double gpu_ms = 0.0;
  for (auto _ : state) {
    std::deque<gpu::Buffer> scratch;
    gpu::CommandList cl(vk);
    // Sorting sorted data costs the same: the passes do not look at the order.
    gpu::record_radix_sort(b->programs(), cl, k, v, kt, vt, n, bits, scratch, ranking);
    cl.mark("sort");
    StageTimes times;
    cl.submit(&times);
    gpu_ms += times.get("gpu_sort");
  }
  state.counters["gpu_ms"] = gpu_ms / static_cast<double>(state.iterations());
  state.counters["pairs"] = n;
}

BENCHMARK_CAPTURE(BM_RadixSort, ballot, gpu::RadixRanking::ballot)
    ->Args({20, 16})
    ->Args({20, 24})
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_RadixSort, compare, gpu::RadixRanking::compare)
    ->Args({20, 16})
    ->Args({20, 24})
    ->Unit(benchmark::kMillisecond);

#define PENUMBRA_GPU_BENCH(method, scene, args)                                             \
  BENCHMARK_CAPTURE(BM_Cpu, method##_##scene, std::string(#method), std::string(#scene))    \
      ->Apply(args);                                                                        \
  BENCHMARK_CAPTURE(BM_Vulkan, method##_##scene, std::string(#method), std::string(#scene)) \
      ->Apply(args)

PENUMBRA_GPU_BENCH(gears, bunny, gears_args);
PENUMBRA_GPU_BENCH(gears, dragon, gears_args);
PENUMBRA_GPU_BENCH(gears, spheres, gears_args);
PENUMBRA_GPU_BENCH(dcs, bunny, raster_args);
PENUMBRA_GPU_BENCH(dcs, dragon, raster_args);
PENUMBRA_GPU_BENCH(dcs, spheres, raster_args);
PENUMBRA_GPU_BENCH(wedges, bunny, raster_args);
PENUMBRA_GPU_BENCH(wedges, dragon, raster_args);
PENUMBRA_GPU_BENCH(wedges, spheres, raster_args);
PENUMBRA_GPU_BENCH(wedge_blend, bunny, raster_args);
PENUMBRA_GPU_BENCH(wedge_blend, dragon, raster_args);
PENUMBRA_GPU_BENCH(wedge_blend, spheres, raster_args);
PENUMBRA_GPU_BENCH(ssm, bunny, raster_args);
PENUMBRA_GPU_BENCH(ssm, dragon, raster_args);
PENUMBRA_GPU_BENCH(ssm, spheres, raster_args);
BENCHMARK_CAPTURE(BM_Cpu, raytrace_bunny, std::string("raytrace"), std::string("bunny"))
    ->Apply(raster_args);
BENCHMARK_CAPTURE(BM_Cpu, raytrace_dragon, std::string("raytrace"), std::string("dragon"))
    ->Apply(raster_args);
BENCHMARK_CAPTURE(BM_Cpu, raytrace_spheres, std::string("raytrace"), std::string("spheres"))
    ->Apply(raster_args);
PENUMBRA_GPU_BENCH(shadow_map, bunny, raster_args);
PENUMBRA_GPU_BENCH(shadow_map, dragon, raster_args);
PENUMBRA_GPU_BENCH(pcss, bunny, raster_args);
PENUMBRA_GPU_BENCH(pcss, dragon, raster_args);
PENUMBRA_GPU_BENCH(silhouette_map, bunny, raster_args);
PENUMBRA_GPU_BENCH(silhouette_map, dragon, raster_args);
PENUMBRA_GPU_BENCH(shadow_volume, bunny, raster_args);
PENUMBRA_GPU_BENCH(shadow_volume, dragon, raster_args);
// Built in: the benchmark of a machine without the models.
PENUMBRA_GPU_BENCH(shadow_map, spheres, raster_args);
PENUMBRA_GPU_BENCH(pcss, spheres, raster_args);
PENUMBRA_GPU_BENCH(shadow_volume, spheres, raster_args);
// The paper's scene classes (seeded, built in).
PENUMBRA_GPU_BENCH(gears, nest, class_args);
PENUMBRA_GPU_BENCH(gears, garden, class_args);
BENCHMARK_CAPTURE(BM_Cpu, raytrace_nest, std::string("raytrace"), std::string("nest"))
    ->Apply(class_args);
BENCHMARK_CAPTURE(BM_Cpu, raytrace_garden, std::string("raytrace"), std::string("garden"))
    ->Apply(class_args);
BENCHMARK_CAPTURE(BM_Sequence, flag, std::string("flag"))->Apply(sequence_args);
BENCHMARK_CAPTURE(BM_Sequence, bunny_orbit, std::string("bunny_orbit"))->Apply(sequence_args);
BENCHMARK_CAPTURE(BM_Sequence, fence_spin, std::string("fence_spin"))->Apply(sequence_args);

}  // namespace
}  // namespace penumbra

#else

static void BM_NoVulkan(benchmark::State& state) {
  for (auto _ : state) state.SkipWithError("built without libvulkan-dev / glslc");
}
BENCHMARK(BM_NoVulkan);

#endif

BENCHMARK_MAIN();
