// Google Benchmark: soft textured shadow volumes [Forest 2008 ch. 5] against the same perforation
// meshed as opaque triangles (scene/alpha_mesh.hpp: one quad per run of opaque texels in a row),
// and against Embree, at the same k×k grid samples, in one run.
//   ./build/release/bench/bench_stsv --benchmark_counters_tabular=true
//   ./build/release/bench/bench_stsv --benchmark_filter='fence/'
// Scenes: `fence` (its 64² slat texture, 2 S-triangles) and `wire` (the fence quad with a wire
// mesh of period 4 texels at resolution R: about 3R²/8 meshed triangles). Args: {image size, k, R}
// (R unused for `fence`). The ratios of interest are DcsMeshed/DcsStsv (the paper's 25–35×) and
// Raytrace/DcsStsv of the same Args; the R sweep gives the cost against texture resolution.
#include <benchmark/benchmark.h>

#include <map>
#include <memory>
#include <string>

#include "penumbra/pipeline/frame.hpp"
#include "penumbra/scene/alpha_mesh.hpp"
#include "penumbra/scene/builtin_scenes.hpp"

namespace penumbra {
namespace {

/// `fence` with a wire-mesh alpha texture of resolution r × r: a texel is wire (opaque) on every
/// fourth row and column.
Scene wire_fence(int r) {
  Scene s = make_builtin_scene("fence");
  Texture& t = s.textures[s.materials[s.meshes[1].material].alpha_texture];
  t.width = t.height = r;
  t.texels.assign(static_cast<size_t>(r) * r, 0.0f);
  for (int y = 0; y < r; ++y)
    for (int x = 0; x < r; ++x) t.texels[static_cast<size_t>(y) * r + x] = x % 4 == 0 || y % 4 == 0;
  return s;
}

struct Fixture {
  std::unique_ptr<Scene> scene;
  std::unique_ptr<Frame> frame;
};

/// The frame of `scene` ("fence" or "wire"), meshed or perforated, cached across iterations.
const Fixture& cached(const std::string& scene, bool meshed, int size, int k, int r) {
  static std::map<std::string, Fixture> cache;
  const std::string key = scene + (meshed ? "/meshed/" : "/alpha/") + std::to_string(size) + "/" +
                          std::to_string(k) + "/" + std::to_string(r);
  auto it = cache.find(key);
  if (it == cache.end()) {
    Scene s = scene.starts_with("wire") ? wire_fence(r) : make_builtin_scene("fence");
    if (meshed) s = with_meshed_alpha(s);
    s.camera.width = s.camera.height = size;
    Fixture f;
    f.scene = std::make_unique<Scene>(std::move(s));
    LightSampleSpec spec;
    spec.pattern = SamplePattern::grid;
    spec.k = k;
    f.frame = std::make_unique<Frame>(*f.scene, spec);
    it = cache.emplace(key, std::move(f)).first;
  }
  return it->second;
}

void run(benchmark::State& state, const std::string& scene, bool meshed, const std::string& method,
         const std::map<std::string, std::string>& options = {}) {
  const int size = static_cast<int>(state.range(0)), k = static_cast<int>(state.range(1)),
            r = static_cast<int>(state.range(2));
  const Fixture& f = cached(scene, meshed, size, k, r);
  const MethodInfo& info = MethodRegistry::builtin().get(method);
  const MethodOptions opts = resolve_options(info, options);
  Counters counters;
  for (auto _ : state) {
    const MethodResult res = f.frame->run(info, opts, false);
    counters = res.per_light[0].counters;
    benchmark::DoNotOptimize(res.per_light[0].lit.data());
  }
  size_t triangles = 0;
  for (const Mesh& m : f.scene->meshes) triangles += m.casts_shadows ? m.triangle_count() : 0;
  state.counters["occluder_triangles"] = static_cast<double>(triangles);
  for (const char* key : {"stsv_pixel_triangle_pairs", "stsv_sample_lookups", "silhouette_edges"})
    if (counters.count(key)) state.counters[key] = counters.at(key);
}

void BM_DcsStsv(benchmark::State& s, const std::string& scene) {
  run(s, scene, false, "dcs");
}
void BM_DcsMeshed(benchmark::State& s, const std::string& scene) {
  run(s, scene, true, "dcs");
}
void BM_Raytrace(benchmark::State& s, const std::string& scene) {
  run(s, scene, false, "raytrace", {{"path", "packet16"}});
}
void BM_RaytraceMeshed(benchmark::State& s, const std::string& scene) {
  run(s, scene, true, "raytrace", {{"path", "packet16"}});
}
void BM_WedgesStsv(benchmark::State& s, const std::string& scene) {
  run(s, scene, false, "wedges");
}

/// The headline: 512² and 1024², k = 8 (64 samples, the paper's largest set) and 16.
void headline(benchmark::internal::Benchmark* b) {
  for (int size : {512, 1024})
    for (int k : {8, 16}) b->Args({size, k, 256});
  b->Unit(benchmark::kMillisecond)->UseRealTime()->MinTime(0.1);
}
/// Cost against texture resolution at 512², k = 8.
void resolutions(benchmark::internal::Benchmark* b) {
  for (int r : {64, 128, 256, 512, 1024}) b->Args({512, 8, r});
  b->Unit(benchmark::kMillisecond)->UseRealTime()->MinTime(0.1);
}

#define PENUMBRA_STSV_SCENE(scene, args)                                         \
  BENCHMARK_CAPTURE(BM_DcsStsv, scene, std::string(#scene))->Apply(args);        \
  BENCHMARK_CAPTURE(BM_DcsMeshed, scene, std::string(#scene))->Apply(args);      \
  BENCHMARK_CAPTURE(BM_Raytrace, scene, std::string(#scene))->Apply(args);       \
  BENCHMARK_CAPTURE(BM_RaytraceMeshed, scene, std::string(#scene))->Apply(args); \
  BENCHMARK_CAPTURE(BM_WedgesStsv, scene, std::string(#scene))->Apply(args);

PENUMBRA_STSV_SCENE(fence, headline)
PENUMBRA_STSV_SCENE(wire, headline)
PENUMBRA_STSV_SCENE(wire_res, resolutions)

}  // namespace
}  // namespace penumbra

BENCHMARK_MAIN();
