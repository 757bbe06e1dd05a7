// Google Benchmark: GEARS [Wang 2014 §4.3] against the Embree baseline at equal samples, in one
// run.
//   ./build/release/bench/bench_gears --benchmark_counters_tabular=true
//   ./build/release/bench/bench_gears --benchmark_filter='/bunny/1024/16$'
// Args: {image size, k (k×k grid samples), grid resolution, light scale ×1..×5}. Scenes: bunny,
// dragon, armadillo and elephant (need scripts/fetch-models.sh), spheres, and the scene classes
// nest (fragmented), garden (alpha-textured foliage) and herd (many dense models). NoPixelCull:
// ablation.
// The ratio of interest is Raytrace/Gears of the same Args (raytrace ignores the grid resolution);
// RaytraceDynamic adds the BVH build a moving scene pays every frame (the paper's "RT dyn."
// column).
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
                std::map<std::string, std::string> options, bool with_bvh_build = false) {
  const bench::Fixture* f = bench::frame_of(state, scene, 0, 1, 3);
  if (method == "gears") options["grid"] = std::to_string(state.range(2));
  bench::time_method(
      state, f, method, options,
      {"triangles_per_cell_avg", "triangles_per_cell_max", "samples_per_cell_avg",
       "samples_per_cell_max", "pairs", "pairs_without_retraction", "assignments_grid",
       "assignments_item", "assignments_total", "assignments_in_volume", "assignments_necessary"},
      [&] {
        if (!with_bvh_build) return;
        EmbreeScene rebuilt(*f->scene);  // a dynamic scene rebuilds its BVH every frame
        benchmark::DoNotOptimize(rebuilt.handle());
      });
}

void BM_Gears(benchmark::State& state, const std::string& scene) {
  run_method(state, scene, "gears", {{"variant", "edge"}});
}
/// Ablation: the same frame without the per-pixel cull (slabs, depth, separating plane).
void BM_GearsNoPixelCull(benchmark::State& state, const std::string& scene) {
  run_method(state, scene, "gears", {{"variant", "edge"}, {"pixel_cull", "false"}});
}
void BM_GearsLut(benchmark::State& state, const std::string& scene) {
  run_method(state, scene, "gears", {{"variant", "lut"}});
}
void BM_Raytrace(benchmark::State& state, const std::string& scene) {
  run_method(state, scene, "raytrace", {{"path", "packet16"}});
}
void BM_RaytraceDynamic(benchmark::State& state, const std::string& scene) {
  run_method(state, scene, "raytrace", {{"path", "packet16"}}, true);
}

/// {size, k, grid (0: the default, grid_resolution's choice), light scale}: the headline (Table 1
/// sizes at k = 16) ...
void headline(benchmark::internal::Benchmark* b) {
  for (int size : {512, 1024}) b->Args({size, 16, 0, 1});
  b->Unit(benchmark::kMillisecond)->UseRealTime()->MinTime(0.5);
}
/// ... and the paper's sweeps at 512²: grid (Table 7), bitmask k (Table 5), light size (Table 6).
void sweeps(benchmark::internal::Benchmark* b) {
  for (int grid : {32, 64, 128, 256}) b->Args({512, 16, grid, 1});
  for (int k : {4, 8, 32}) b->Args({512, k, 0, 1});
  for (int scale : {2, 3, 4, 5}) b->Args({512, 16, 0, scale});
  b->Unit(benchmark::kMillisecond)->UseRealTime()->MinTime(0.5);
}

BENCHMARK_CAPTURE(BM_Raytrace, bunny, std::string("bunny"))->Apply(headline);
BENCHMARK_CAPTURE(BM_RaytraceDynamic, bunny, std::string("bunny"))->Apply(headline);
BENCHMARK_CAPTURE(BM_Gears, bunny, std::string("bunny"))->Apply(headline);
BENCHMARK_CAPTURE(BM_GearsLut, bunny, std::string("bunny"))->Apply(headline);
BENCHMARK_CAPTURE(BM_Raytrace, dragon, std::string("dragon"))->Apply(headline);
BENCHMARK_CAPTURE(BM_Gears, dragon, std::string("dragon"))->Apply(headline);
BENCHMARK_CAPTURE(BM_Raytrace, spheres, std::string("spheres"))->Apply(headline);
BENCHMARK_CAPTURE(BM_Gears, spheres, std::string("spheres"))->Apply(headline);
BENCHMARK_CAPTURE(BM_Raytrace, armadillo, std::string("armadillo"))->Apply(headline);
BENCHMARK_CAPTURE(BM_Gears, armadillo, std::string("armadillo"))->Apply(headline);
BENCHMARK_CAPTURE(BM_Raytrace, elephant, std::string("elephant"))->Apply(headline);
BENCHMARK_CAPTURE(BM_Gears, elephant, std::string("elephant"))->Apply(headline);
BENCHMARK_CAPTURE(BM_Raytrace, nest, std::string("nest"))->Apply(headline);
BENCHMARK_CAPTURE(BM_Gears, nest, std::string("nest"))->Apply(headline);
BENCHMARK_CAPTURE(BM_Raytrace, garden, std::string("garden"))->Apply(headline);
BENCHMARK_CAPTURE(BM_Gears, garden, std::string("garden"))->Apply(headline);
BENCHMARK_CAPTURE(BM_Raytrace, herd, std::string("herd"))->Apply(headline);
BENCHMARK_CAPTURE(BM_Gears, herd, std::string("herd"))->Apply(headline);
BENCHMARK_CAPTURE(BM_GearsNoPixelCull, bunny, std::string("bunny"))->Apply(headline);
BENCHMARK_CAPTURE(BM_GearsNoPixelCull, elephant, std::string("elephant"))->Apply(headline);
BENCHMARK_CAPTURE(BM_Gears, bunny_sweep, std::string("bunny"))->Apply(sweeps);
BENCHMARK_CAPTURE(BM_Raytrace, bunny_sweep, std::string("bunny"))->Apply(sweeps);

}  // namespace
}  // namespace penumbra

BENCHMARK_MAIN();
