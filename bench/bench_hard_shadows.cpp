// Google Benchmark: the hard-shadow methods and PCSS against the Embree baseline.
//   ./build/h-hard/bench/bench_hard_shadows --benchmark_counters_tabular=true
// Scene: bunny (needs scripts/fetch-models.sh), 1024×1024, all cores; light samples k = 1 (the
// light centre) and 16×16 grid. shadow_volume, shadow_map and pcss ignore k (they use the light
// centre / the light's size); raytrace traces k² rays per pixel. Compare ratios within one run.
#include <benchmark/benchmark.h>

#include <map>
#include <memory>
#include <string>

#include "bench_fixture.hpp"
#include "penumbra/pipeline/frame.hpp"
#include "penumbra/scene/builtin_scenes.hpp"
#include "penumbra/scene/model_paths.hpp"

namespace penumbra {
namespace {

void run_method(benchmark::State& state, const std::string& method) {
  bench::time_method(state, bench::frame_of(state, "bunny", 0, 1, -1), method, {});
}

void BM_Raytrace(benchmark::State& state) {
  run_method(state, "raytrace");
}
void BM_ShadowVolume(benchmark::State& state) {
  run_method(state, "shadow_volume");
}
void BM_ShadowMap(benchmark::State& state) {
  run_method(state, "shadow_map");
}
void BM_Pcss(benchmark::State& state) {
  run_method(state, "pcss");
}

#define PENUMBRA_HARD_BENCH(fn) \
  BENCHMARK(fn)->Args({1024, 1})->Args({1024, 16})->Unit(benchmark::kMillisecond)->UseRealTime()

PENUMBRA_HARD_BENCH(BM_Raytrace);
PENUMBRA_HARD_BENCH(BM_ShadowVolume);
PENUMBRA_HARD_BENCH(BM_ShadowMap);
PENUMBRA_HARD_BENCH(BM_Pcss);

}  // namespace
}  // namespace penumbra

BENCHMARK_MAIN();
