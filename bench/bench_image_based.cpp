// Google Benchmark: the image-based soft-shadow methods — `ssm` (Atty 2006)
// one-pass and two-pass, `silhouette_map` hard and soft (Valient & Bujnak) — against `pcss` and
// `raytrace` (16×16 grid samples) on bunny, 1024×1024, all cores; then `ssm` time vs the
// occluder-map resolution (32…512, the paper's Fig. 22) and vs the light size (×1, ×2, ×3 of the
// scene's 0.5 side, Fig. 23).
//   scripts/build.sh release --target bench_image_based
//   ./build/release/bench/bench_image_based --benchmark_counters_tabular=true
// Needs scripts/fetch-models.sh (bunny); every benchmark is skipped with a message otherwise.
// Times are the method's own (Frame::run: G-buffer and BVH built once, outside the loop).
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

void run_method(benchmark::State& state, const std::string& method,
                const std::map<std::string, std::string>& options, int size, int k,
                int light_scale = 1) {
  bench::time_method(state, bench::cached_frame("bunny", size, k, static_cast<float>(light_scale)),
                     method, options, {"occluder_texels", "penumbra_texels", "silhouette_faces"});
}

constexpr int kSize = 1024;

// --- Methods at 1024² -------------------------------------------------------------------------
void BM_SsmOnePass(benchmark::State& state) {
  run_method(state, "ssm", {{"two_pass", "false"}}, kSize, 1);
}
void BM_SsmTwoPass(benchmark::State& state) {
  run_method(state, "ssm", {{"two_pass", "true"}}, kSize, 1);
}
void BM_SilhouetteMapHard(benchmark::State& state) {
  run_method(state, "silhouette_map", {{"mode", "hard"}}, kSize, 1);
}
void BM_SilhouetteMapSoft(benchmark::State& state) {
  run_method(state, "silhouette_map", {{"mode", "soft"}}, kSize, 1);
}
void BM_Pcss(benchmark::State& state) {
  run_method(state, "pcss", {}, kSize, 1);
}
void BM_Raytrace16x16(benchmark::State& state) {
  run_method(state, "raytrace", {}, kSize, 16);
}

#define PENUMBRA_IMAGE_BENCH(fn) \
  BENCHMARK(fn)->Unit(benchmark::kMillisecond)->UseRealTime()->MeasureProcessCPUTime()

PENUMBRA_IMAGE_BENCH(BM_SsmOnePass);
PENUMBRA_IMAGE_BENCH(BM_SsmTwoPass);
PENUMBRA_IMAGE_BENCH(BM_SilhouetteMapHard);
PENUMBRA_IMAGE_BENCH(BM_SilhouetteMapSoft);
PENUMBRA_IMAGE_BENCH(BM_Pcss);
PENUMBRA_IMAGE_BENCH(BM_Raytrace16x16)->Iterations(2);

// --- ssm vs occluder-map resolution (Fig. 22) and light size (Fig. 23) -------------------------
void BM_SsmResolution(benchmark::State& state) {
  run_method(state, "ssm",
             {{"resolution", std::to_string(state.range(0))},
              {"two_pass", state.range(1) ? "true" : "false"}},
             kSize, 1);
}
BENCHMARK(BM_SsmResolution)
    ->ArgNames({"res", "two_pass"})
    ->ArgsProduct({{32, 64, 128, 256, 512}, {0, 1}})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

void BM_SsmLightSize(benchmark::State& state) {
  run_method(state, "ssm", {{"resolution", std::to_string(state.range(1))}, {"two_pass", "false"}},
             kSize, 1, static_cast<int>(state.range(0)));
}
BENCHMARK(BM_SsmLightSize)
    ->ArgNames({"light_x", "res"})
    ->ArgsProduct({{1, 2, 3}, {128, 256}})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

}  // namespace
}  // namespace penumbra

BENCHMARK_MAIN();
