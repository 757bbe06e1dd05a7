// Google Benchmark: `wedges` and `wedge_blend` against `raytrace` (16×16 samples) in one process
//, and how their cost grows with the light's size and the resolution, beside the
// "pixels inside wedges" counter (Assarsson 2003 III §5 / IV §6: cost follows the pixels inside
// wedges).
//   ./build/release/bench/bench_wedges --benchmark_counters_tabular=true
// Scenes: bunny (needs scripts/fetch-models.sh) and spheres. Args: {size, k, light scale}.
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

void run_method(benchmark::State& state, const std::string& scene, const std::string& method,
                const std::map<std::string, std::string>& options) {
  const std::optional<Visibility> v =
      bench::time_method(state, bench::frame_of(state, scene), method, options,
                         {"pixels_inside_wedges", "pixel_tests", "wedges", "rays"});
  if (v && v->counters.count("wedges")) {  // the last iteration's stage times
    state.counters["pass2_ms"] = v->times.get("pass2") + v->times.get("pass2_blend");
    state.counters["wedge_setup_ms"] = v->times.get("wedges");
  }
}

void BM_Wedges(benchmark::State& state, const std::string& scene) {
  run_method(state, scene, "wedges", {});
}
void BM_WedgeBlend(benchmark::State& state, const std::string& scene) {
  run_method(state, scene, "wedge_blend", {});
}
/// Paper III §3.3's coverage texture (n = 32, bilinear) instead of the analytic area.
void BM_WedgesTexture(benchmark::State& state, const std::string& scene) {
  run_method(state, scene, "wedges", {{"coverage", "texture"}});
}
void BM_Raytrace(benchmark::State& state, const std::string& scene) {
  run_method(state, scene, "raytrace", {{"path", "packet16"}});
}

/// {size, k, scale}: 1024² at ×1, ×2, ×3 light; 512² and 2048² at ×1.
void wedge_args(benchmark::internal::Benchmark* b) {
  b->Args({1024, 1, 1})->Args({1024, 1, 2})->Args({1024, 1, 3});
  b->Args({512, 1, 1})->Args({2048, 1, 1});
  b->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(2);
}

BENCHMARK_CAPTURE(BM_Raytrace, bunny, std::string("bunny"))
    ->Args({1024, 16, 1})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime()
    ->Iterations(1);
BENCHMARK_CAPTURE(BM_Wedges, bunny, std::string("bunny"))->Apply(wedge_args);
BENCHMARK_CAPTURE(BM_WedgeBlend, bunny, std::string("bunny"))->Apply(wedge_args);
BENCHMARK_CAPTURE(BM_WedgesTexture, bunny, std::string("bunny"))
    ->Args({1024, 1, 1})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime()
    ->Iterations(2);
BENCHMARK_CAPTURE(BM_Raytrace, spheres, std::string("spheres"))
    ->Args({1024, 16, 1})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime()
    ->Iterations(1);
BENCHMARK_CAPTURE(BM_Wedges, spheres, std::string("spheres"))->Apply(wedge_args);
BENCHMARK_CAPTURE(BM_WedgeBlend, spheres, std::string("spheres"))->Apply(wedge_args);
BENCHMARK_CAPTURE(BM_WedgesTexture, spheres, std::string("spheres"))
    ->Args({1024, 1, 1})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime()
    ->Iterations(2);

}  // namespace
}  // namespace penumbra

BENCHMARK_MAIN();
