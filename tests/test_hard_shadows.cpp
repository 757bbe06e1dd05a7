// The hard-shadow methods on whole frames: shadow_volume against raytrace with the light centre
// (one grid sample), its per-pixel counts against brute force, shadow_map convergence, pcss.
#include <gtest/gtest.h>
#include <tbb/task_arena.h>

#include <cmath>
#include <cstdio>

#include "penumbra/core/error.hpp"
#include "penumbra/render/receivers.hpp"
#include "penumbra/scene/model_paths.hpp"
#include "penumbra/scene/shapes.hpp"
#include "penumbra/shadows/wedges/shadow_volume.hpp"
#include "support/frame_helpers.hpp"

namespace penumbra {
namespace {

using test::centre_sample;
using test::make_test_frame;
using test::TestFrame;
using test::without_alpha;

struct Agreement {
  int active = 0, differ = 0, shadowed = 0;
};

Agreement compare_with_raytrace(const TestFrame& t, const std::string& method = "shadow_volume") {
  const MethodResult a = t.run(method);
  const MethodResult rt = t.run("raytrace");
  Agreement r;
  for (size_t i = 0; i < a.per_light[0].lit.size(); ++i) {
    if (t.frame->receivers(0)[i] != kActive) continue;
    ++r.active;
    r.shadowed += rt.per_light[0].lit[i] < 0.5f;
    r.differ += (a.per_light[0].lit[i] < 0.5f) != (rt.per_light[0].lit[i] < 0.5f);
  }
  return r;
}

/// ≥ 99.99 % of the active pixels identical (at most 1 in 10 000 may differ).
void expect_equal_to_raytrace(const TestFrame& t, int min_shadowed) {
  const Agreement r = compare_with_raytrace(t);
  std::printf("    %d of %d active pixels differ, %d shadowed\n", r.differ, r.active, r.shadowed);
  EXPECT_LE(r.differ, r.active / 10000)
      << r.differ << " of " << r.active << " active pixels differ";
  EXPECT_GE(r.shadowed, min_shadowed);
}

TEST(ShadowVolume, EqualsRaytraceOnQuad) {
  expect_equal_to_raytrace(make_test_frame("quad", 128, 128, centre_sample()), 1000);
}

TEST(ShadowVolume, EqualsRaytraceOnSpheres) {
  expect_equal_to_raytrace(make_test_frame("spheres", 128, 128, centre_sample()), 1000);
}

TEST(ShadowVolume, EqualsRaytraceWithAPointLight) {
  Scene s = make_builtin_scene("spheres");
  s.lights[0].shape = LightShape::point;
  expect_equal_to_raytrace(make_test_frame(std::move(s), 128, 128, centre_sample()), 1000);
}

/// Alpha is ignored by shadow volumes (the fence is an opaque quad to them; soft textured shadow
/// volumes are Forest 2008 ch. 5): compared with raytrace on the same scene without its alpha
/// texture.
TEST(ShadowVolume, EqualsRaytraceOnFenceWithAlphaIgnored) {
  expect_equal_to_raytrace(
      make_test_frame(without_alpha(make_builtin_scene("fence")), 128, 128, centre_sample()), 1000);
}

/// The procedural closed box and sphere (and the open fence quad) of the default scene.
TEST(ShadowVolume, EqualsRaytraceOnClosedBoxAndSphere) {
  expect_equal_to_raytrace(
      make_test_frame(without_alpha(make_builtin_scene("default")), 128, 128, centre_sample()),
      1000);
}

TEST(ShadowVolume, EqualsRaytraceOnBunny) {
  if (!find_model("bunny00.off")) GTEST_SKIP() << "bunny not fetched: run scripts/fetch-models.sh";
  expect_equal_to_raytrace(make_test_frame("bunny", 128, 128, centre_sample()), 200);
}

/// Open, non-manifold and inconsistently oriented meshes: a sphere with a band of triangles
/// removed (open), a third of its remaining triangles flipped, and a fin of three triangles on one
/// edge; lit from the side so the open part matters.
TEST(ShadowVolume, EqualsRaytraceOnOpenNonManifoldMesh) {
  expect_equal_to_raytrace(
      make_test_frame(test::open_non_manifold_scene(), 128, 128, centre_sample()), 500);
}

/// The camera stands inside the occluder's shadow volume (between the quad and the ground): z-fail
/// needs no count at the camera, so the umbra around it is still right.
TEST(ShadowVolume, CameraInsideTheShadowVolume) {
  Scene s = make_builtin_scene("quad");
  s.camera.position = Vec3(0.1f, 0.5f, 0.15f);
  s.camera.target = Vec3(0.9f, 0.0f, 1.1f);
  s.camera.vfov_deg = 70.0f;
  const auto t = make_test_frame(std::move(s), 96, 96, centre_sample());
  const Agreement r = compare_with_raytrace(t);
  EXPECT_LE(r.differ, r.active / 10000);
  EXPECT_GT(r.shadowed, 500);
  EXPECT_GT(r.active - r.shadowed, 500);
}

/// The per-pixel count is the number of caster triangles the segment to the light crosses.
TEST(ShadowVolume, CountsAreCrossingNumbers) {
  Scene s = make_builtin_scene("spheres");
  const auto t = make_test_frame(std::move(s), 64, 64, centre_sample());
  const Frame& f = *t.frame;
  ShadowVolumeStats stats;
  const Image<int32_t> counts = shadow_volume_counts(
      f.scene(), f.scene().camera, f.gbuffer(), f.receivers(0), f.scene().lights[0].center, &stats);
  EXPECT_GT(stats.silhouette_edges, 100u);
  const GBuffer& g = f.gbuffer();
  const DVec3 light(f.scene().lights[0].center);
  int checked = 0, differ = 0, max_count = 0;
  for (size_t i = 0; i < g.pixel_count(); i += 3) {
    if (f.receivers(0)[i] != kActive) continue;
    const DVec3 o(g.shadow_origin(i)), d = light - o;
    int crossings = 0;
    for (const Mesh& m : f.scene().meshes)
      for (size_t tri = 0; tri < m.triangle_count(); ++tri)
        crossings += test::segment_crosses_triangle(
            o, d, DVec3(m.vertex(tri, 0)), DVec3(m.vertex(tri, 1)), DVec3(m.vertex(tri, 2)));
    ++checked;
    differ += counts[i] != crossings;
    max_count = std::max(max_count, crossings);
  }
  EXPECT_GT(checked, 800);
  EXPECT_LE(differ, checked / 500);  // grazing segments through shared edges may count 1 off
  EXPECT_GE(max_count, 4);           // behind two spheres: 2 crossings each
}

TEST(ShadowVolume, SameCountsForAnyThreadCount) {
  const auto t = make_test_frame("spheres", 64, 64, centre_sample());
  const Frame& f = *t.frame;
  const auto run = [&] {
    return shadow_volume_counts(f.scene(), f.scene().camera, f.gbuffer(), f.receivers(0),
                                f.scene().lights[0].center);
  };
  const Image<int32_t> many = run();
  tbb::task_arena one(1);
  Image<int32_t> single;
  one.execute([&] { single = run(); });
  EXPECT_EQ(many.pixels(), single.pixels());
}

double mean_abs_diff(const TestFrame& t, const MethodResult& a, const MethodResult& b) {
  double sum = 0.0;
  int n = 0;
  for (size_t i = 0; i < a.per_light[0].lit.size(); ++i) {
    if (t.frame->receivers(0)[i] != kActive) continue;
    sum += std::abs(a.per_light[0].lit[i] - b.per_light[0].lit[i]);
    ++n;
  }
  return sum / std::max(n, 1);
}

TEST(ShadowMap, ConvergesToShadowVolumeAsResolutionGrows) {
  const auto t = make_test_frame("spheres", 96, 96, centre_sample());
  const MethodResult sv = t.run("shadow_volume");
  double previous = 1.0;
  for (const char* res : {"256", "512", "1024", "2048"}) {
    const double e = mean_abs_diff(t, t.run("shadow_map", {{"resolution", res}}), sv);
    std::printf("    shadow_map %s: mean |error| vs shadow_volume %.5f\n", res, e);
    EXPECT_LT(e, previous) << "resolution " << res;
    previous = e;
  }
  EXPECT_LT(previous, 0.01);  // 2048²: about 1 % of the pixels, all on shadow boundaries
}

TEST(ShadowMap, PcfGivesFractionsAndOptionsWork) {
  const auto t = make_test_frame("quad", 64, 64, centre_sample());
  const MethodResult hard = t.run("shadow_map", {{"resolution", "256"}});
  const MethodResult pcf = t.run("shadow_map", {{"resolution", "256"}, {"pcf", "5"}});
  int fractional = 0;
  for (size_t i = 0; i < pcf.per_light[0].lit.size(); ++i) {
    const float v = pcf.per_light[0].lit[i];
    EXPECT_GE(v, 0.0f);
    EXPECT_LE(v, 1.0f);
    fractional += v > 0.0f && v < 1.0f;
    const float h = hard.per_light[0].lit[i];
    EXPECT_TRUE(h == 0.0f || h == 1.0f);
  }
  EXPECT_GT(fractional, 20);
  // Both faces in the map: the same hard shadow.
  const MethodResult back = t.run("shadow_map", {{"resolution", "256"}, {"faces", "both"}});
  EXPECT_LT(mean_abs_diff(t, back, t.run("shadow_volume")), 0.01);
  EXPECT_THROW(t.run("shadow_map", {{"pcf", "0"}}), Error);
}

TEST(Pcss, SoftensTowardTheExactPenumbraOnQuad) {
  LightSampleSpec spec;
  spec.k = 1;
  const auto t = make_test_frame("quad", 64, 64, spec);
  const MethodResult exact = t.run("exact");
  const double pcss_error = mean_abs_diff(t, t.run("pcss", {{"resolution", "512"}}), exact);
  const double hard_error = mean_abs_diff(t, t.run("shadow_volume"), exact);
  // PCSS is the approximate baseline (no bound from the issue); it must at least beat the hard
  // shadow it starts from on the scene whose penumbra it models best.
  EXPECT_LT(pcss_error, 0.6 * hard_error);
  EXPECT_GT(hard_error, 0.01);
}

}  // namespace
}  // namespace penumbra
