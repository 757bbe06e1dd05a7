// Google Benchmark: the stages every `penumbra render` pays once per frame, whatever the method —
// the mesh file's validation and import, the Embree device and BVH, the G-buffer, the receiver
// classes, the closed-form unshadowed irradiance and the output files.
//   ./build/release/bench/bench_frame --benchmark_counters_tabular=true
// Bunny (needs scripts/fetch-models.sh) at 1024×1024, as `render --scene bunny --size 1024x1024`.
#include <benchmark/benchmark.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "bench_fixture.hpp"
#include "penumbra/core/parallel.hpp"
#include "penumbra/io/image_io.hpp"
#include "penumbra/pipeline/outputs.hpp"
#include "penumbra/pipeline/shading.hpp"
#include "penumbra/render/receivers.hpp"
#include "penumbra/scene/mesh_header.hpp"
#include "penumbra/scene/mesh_loader.hpp"

namespace penumbra {
namespace {

constexpr int kSize = 1024;

const bench::Fixture* bunny(benchmark::State& state) {
  const bench::Fixture* f = bench::cached_frame("bunny", kSize, 1);
  if (!f) state.SkipWithError(bench::kNotFetched);
  return f;
}

std::filesystem::path scratch_dir() {
  const std::filesystem::path dir = std::filesystem::temp_directory_path() / "penumbra_bench_frame";
  std::filesystem::create_directories(dir);
  return dir;
}

/// Our validation walk alone (mesh_header.hpp), on the bytes already in memory.
void BM_ValidateOff(benchmark::State& state) {
  const std::optional<std::filesystem::path> path = find_model("bunny00.off");
  if (!path) return state.SkipWithError(bench::kNotFetched);
  std::ifstream in(*path, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  const std::string bytes = std::move(text).str();
  for (auto _ : state) benchmark::DoNotOptimize(validate_mesh_file(bytes, ".off"));
}

/// The whole mesh load: read, validate, assimp import, merge.
void BM_LoadMeshFile(benchmark::State& state) {
  const std::optional<std::filesystem::path> path = find_model("bunny00.off");
  if (!path) return state.SkipWithError(bench::kNotFetched);
  for (auto _ : state) benchmark::DoNotOptimize(load_mesh_file(*path).triangles.data());
}

/// The built-in scene: the mesh load plus the scene's own checks and framing.
void BM_LoadScene(benchmark::State& state) {
  if (!bench::scene_available("bunny")) return state.SkipWithError(bench::kNotFetched);
  for (auto _ : state) benchmark::DoNotOptimize(make_builtin_scene("bunny").meshes.data());
}

/// Device creation and BVH build, as every Frame pays them.
void BM_EmbreeScene(benchmark::State& state) {
  const bench::Fixture* f = bunny(state);
  if (!f) return;
  double build_ms = 0.0;
  for (auto _ : state) {
    const EmbreeScene embree(*f->scene);
    build_ms = embree.build_ms();
  }
  state.counters["bvh_build_ms"] = build_ms;
}

void BM_GBuffer(benchmark::State& state) {
  const bench::Fixture* f = bunny(state);
  if (!f) return;
  for (auto _ : state)
    benchmark::DoNotOptimize(render_gbuffer(f->frame->embree(), f->scene->camera).depth.data());
}

void BM_Receivers(benchmark::State& state) {
  const bench::Fixture* f = bunny(state);
  if (!f) return;
  for (auto _ : state)
    benchmark::DoNotOptimize(
        classify_receivers(f->frame->gbuffer(), f->scene->lights.front()).data());
}

/// The closed-form unshadowed irradiance at every active pixel (what Frame::unshadowed computes).
void BM_Irradiance(benchmark::State& state) {
  const bench::Fixture* f = bunny(state);
  if (!f) return;
  const GBuffer& g = f->frame->gbuffer();
  const Image<uint8_t>& classes = f->frame->receivers(0);
  const LightIrradiance irradiance(*f->scene, f->scene->lights.front());
  Image<Vec3> e(g.width, g.height, Vec3(0.0f));
  for (auto _ : state) {
    irradiance.fill(g, classes, e);
    benchmark::DoNotOptimize(e.data());
  }
}

/// The same pixels one at() each: the scalar path fill's batches replace.
void BM_IrradianceScalar(benchmark::State& state) {
  const bench::Fixture* f = bunny(state);
  if (!f) return;
  const GBuffer& g = f->frame->gbuffer();
  const Image<uint8_t>& classes = f->frame->receivers(0);
  const LightIrradiance irradiance(*f->scene, f->scene->lights.front());
  Image<Vec3> e(g.width, g.height, Vec3(0.0f));
  for (auto _ : state) {
    parallel_rows(g.height, [&](int y) {
      for (int x = 0; x < g.width; ++x) {
        const size_t i = static_cast<size_t>(y) * g.width + x;
        if (classes[i] == kActive) e[i] = irradiance.at(g.shadow_origin(i), g.shading_normal[i]);
      }
    });
    benchmark::DoNotOptimize(e.data());
  }
}

void BM_WritePng(benchmark::State& state) {
  const bench::Fixture* f = bunny(state);
  if (!f) return;
  const Image<Vec3>& e = f->frame->unshadowed(0);
  const std::filesystem::path path = scratch_dir() / "beauty.png";
  for (auto _ : state) write_png_rgb(path, e);
  state.counters["bytes"] = static_cast<double>(std::filesystem::file_size(path));
}

void BM_WriteExr(benchmark::State& state) {
  const bench::Fixture* f = bunny(state);
  if (!f) return;
  const MethodInfo& info = MethodRegistry::builtin().get("shadow_map");
  const MethodResult result = f->frame->run(info, resolve_options(info, {}), false);
  const std::filesystem::path dir = scratch_dir();
  for (auto _ : state) write_visibility(dir, *f->frame, result, FloatFormat::exr);
  state.counters["bytes"] = static_cast<double>(std::filesystem::file_size(dir / "visibility.exr"));
}

BENCHMARK(BM_ValidateOff)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_LoadMeshFile)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_LoadScene)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_EmbreeScene)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_GBuffer)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_Receivers)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_Irradiance)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_IrradianceScalar)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_WritePng)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_WriteExr)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace
}  // namespace penumbra

BENCHMARK_MAIN();
