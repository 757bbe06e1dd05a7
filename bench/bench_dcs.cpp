// Google Benchmark: depth complexity sampling [Forest 2008 ch. 4] against Embree (packets) and
// GEARS at the same k×k grid samples, in one run.
//   ./build/release/bench/bench_dcs --benchmark_counters_tabular=true
//   ./build/release/bench/bench_dcs --benchmark_filter='bunny/1024'
// Args: {image size, k, light scale ×1..×5}. Scenes: bunny, dragon, armadillo, elephant (need
// scripts/fetch-models.sh), spheres, nest, garden, herd. The ratios of interest are Raytrace/Dcs
// and Gears/Dcs of the same Args; DcsCentre is the inexact light-centre silhouette (Forest
// fig. 4.3a) for its cost.
#include <benchmark/benchmark.h>

#include <map>
#include <string>

#include "bench_fixture.hpp"

namespace penumbra {
namespace {

void run_method(benchmark::State& state, const std::string& scene, const std::string& method,
                const std::map<std::string, std::string>& options) {
  bench::time_method(state, bench::frame_of(state, scene), method, options,
                     {"silhouette_edges", "straddling_edges", "edges_per_penumbra_pixel",
                      "covered_updates_per_pixel", "counter_max"});
}

void BM_Dcs(benchmark::State& state, const std::string& scene) {
  run_method(state, scene, "dcs", {});
}
void BM_DcsCentre(benchmark::State& state, const std::string& scene) {
  run_method(state, scene, "dcs", {{"silhouettes", "centre"}});
}
void BM_Raytrace(benchmark::State& state, const std::string& scene) {
  run_method(state, scene, "raytrace", {{"path", "packet16"}});
}
void BM_Gears(benchmark::State& state, const std::string& scene) {
  run_method(state, scene, "gears", {});
}

/// {size, k, light scale}: the headline at k = 16 ...
void headline(benchmark::internal::Benchmark* b) {
  b->Args({1024, 16, 1});
  b->Unit(benchmark::kMillisecond)->UseRealTime()->MinTime(0.1);
}
void small(benchmark::internal::Benchmark* b) {
  b->Args({512, 16, 1});
  b->Unit(benchmark::kMillisecond)->UseRealTime()->MinTime(0.1);
}
/// ... and the sweeps at 512²: k = 4…32, light size ×1…×5.
void sweeps(benchmark::internal::Benchmark* b) {
  for (int k : {4, 8, 16, 32}) b->Args({512, k, 1});
  for (int scale : {2, 3, 4, 5}) b->Args({512, 16, scale});
  b->Unit(benchmark::kMillisecond)->UseRealTime()->MinTime(0.1);
}

#define PENUMBRA_DCS_SCENE(scene, sizes)                                     \
  BENCHMARK_CAPTURE(BM_Dcs, scene, std::string(#scene))->Apply(sizes);       \
  BENCHMARK_CAPTURE(BM_DcsCentre, scene, std::string(#scene))->Apply(sizes); \
  BENCHMARK_CAPTURE(BM_Raytrace, scene, std::string(#scene))->Apply(sizes);  \
  BENCHMARK_CAPTURE(BM_Gears, scene, std::string(#scene))->Apply(sizes);

PENUMBRA_DCS_SCENE(bunny, headline)
PENUMBRA_DCS_SCENE(dragon, headline)
PENUMBRA_DCS_SCENE(armadillo, headline)
PENUMBRA_DCS_SCENE(elephant, headline)
PENUMBRA_DCS_SCENE(spheres, small)
// The scene classes at 512² only: every twig and leaf edge is a silhouette, so dcs takes seconds.
PENUMBRA_DCS_SCENE(nest, small)
PENUMBRA_DCS_SCENE(garden, small)
PENUMBRA_DCS_SCENE(herd, small)
BENCHMARK_CAPTURE(BM_Dcs, bunny_sweep, std::string("bunny"))->Apply(sweeps);
BENCHMARK_CAPTURE(BM_Raytrace, bunny_sweep, std::string("bunny"))->Apply(sweeps);
BENCHMARK_CAPTURE(BM_Gears, bunny_sweep, std::string("bunny"))->Apply(sweeps);

}  // namespace
}  // namespace penumbra

BENCHMARK_MAIN();
