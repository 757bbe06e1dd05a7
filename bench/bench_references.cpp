// Google Benchmark: the Embree baseline every exact method is measured against.
//   ./build/release/bench/bench_references --benchmark_counters_tabular=true
// Scenes: bunny (needs scripts/fetch-models.sh) and spheres; 512×512; 16×16 grid samples.
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
  const bench::Fixture* f = bench::frame_of(state, scene, 0, 1, -1);
  const std::optional<Visibility> v = bench::time_method(state, f, method, options);
  if (!v) return;
  if (v->counters.count("rays"))
    state.counters["rays_per_s"] =
        benchmark::Counter(v->counters.at("rays"), benchmark::Counter::kIsIterationInvariantRate);
  state.counters["bvh_build_ms"] = f->frame->embree().build_ms();
}

void BM_RaytracePacket16(benchmark::State& state, const std::string& scene) {
  run_method(state, scene, "raytrace", {{"path", "packet16"}});
}
void BM_RaytraceSingle(benchmark::State& state, const std::string& scene) {
  run_method(state, scene, "raytrace", {{"path", "single"}});
}

/// The BVH build alone (a dynamic scene pays it every frame).
void BM_EmbreeBuild(benchmark::State& state, const std::string& scene_name) {
  if (scene_name == "bunny" && !find_model("bunny00.off")) {
    state.SkipWithError("bunny not fetched: run scripts/fetch-models.sh");
    return;
  }
  const Scene scene = make_builtin_scene(scene_name);
  for (auto _ : state) {
    EmbreeScene embree(scene);
    benchmark::DoNotOptimize(embree.handle());
  }
}

BENCHMARK_CAPTURE(BM_RaytracePacket16, bunny, std::string("bunny"))
    ->Args({512, 16})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK_CAPTURE(BM_RaytraceSingle, bunny, std::string("bunny"))
    ->Args({512, 16})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK_CAPTURE(BM_RaytracePacket16, spheres, std::string("spheres"))
    ->Args({512, 16})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK_CAPTURE(BM_EmbreeBuild, bunny, std::string("bunny"))
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

}  // namespace
}  // namespace penumbra

BENCHMARK_MAIN();
