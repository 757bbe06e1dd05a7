// Google Benchmark: the GPU radix sort of the GEARS pipeline (gpu/sort.hpp), its two block
// rankings on the same keys — subgroup ballots (linear in the block size) and byte compares
// (quadratic, the fallback of devices without ballots). Counter gpu_ms: the sort's GPU time from
// timestamp queries; the wall time includes submission and wait.
//   ./build/release/bench/bench_vulkan_sort --benchmark_counters_tabular=true
// Args: {log2 of the pair count, key bits}. Skipped without a Vulkan device.
#include <benchmark/benchmark.h>

#ifdef PENUMBRA_HAVE_VULKAN

#include <deque>
#include <memory>
#include <random>
#include <vector>

#include "penumbra/gpu/backend.hpp"
#include "penumbra/gpu/sort.hpp"

namespace penumbra {
namespace {

gpu::Backend* backend() {
  static const std::unique_ptr<gpu::Backend> b = []() -> std::unique_ptr<gpu::Backend> {
    if (!gpu::vulkan_available()) return nullptr;
    return std::make_unique<gpu::Backend>();
  }();
  return b.get();
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

}  // namespace
}  // namespace penumbra

#else

static void BM_NoVulkan(benchmark::State& state) {
  for (auto _ : state) state.SkipWithError("built without libvulkan-dev / glslc");
}
BENCHMARK(BM_NoVulkan);

#endif

BENCHMARK_MAIN();
