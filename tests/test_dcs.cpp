// Depth complexity sampling [Forest 2008 ch. 4]: with silhouettes w.r.t. the whole light, the
// same per-sample answer as `raytrace` (and `gears`) on the same samples — closed, open, flipped
// and non-manifold meshes, rectangle/disk/sphere/point lights, k = 4…32, every sample pattern;
// textured lights in RGB; semi-opaque occluders (exact product and the paper's approximation);
// and the under-estimated penumbra of the light-centre silhouettes (fig. 4.3a).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "penumbra/pipeline/shading.hpp"
#include "penumbra/render/receivers.hpp"
#include "penumbra/scene/model_paths.hpp"
#include "penumbra/scene/shapes.hpp"
#include "penumbra/shadows/wedges/dcs_counters.hpp"
#include "support/frame_helpers.hpp"
#include "support/mask_agreement.hpp"

namespace penumbra {
namespace {

using test::expect_equal_masks;
using test::make_test_frame;
using test::MaskAgreement;
using test::TestFrame;

LightSampleSpec pattern(SamplePattern p, int k) {
  return test::sample_spec(p, k, 5);
}
using test::grid_samples;

MaskAgreement compare_masks(const TestFrame& t,
                            const std::map<std::string, std::string>& options = {},
                            bool classify = true) {
  return test::compare_masks(t, "dcs", options, classify);
}

/// Mean |V_a − V_b| over the active pixels, and the largest difference.
struct VDiff {
  double mean = 0.0, max = 0.0;
};
VDiff v_diff(const TestFrame& t, const Image<float>& a, const Image<float>& b) {
  VDiff d;
  size_t n = 0;
  for (size_t i = 0; i < a.size(); ++i) {
    if (t.frame->receivers(0)[i] != kActive) continue;
    const double e = std::abs(static_cast<double>(a[i]) - b[i]);
    d.mean += e;
    d.max = std::max(d.max, e);
    ++n;
  }
  d.mean /= std::max<size_t>(1, n);
  return d;
}

TEST(Dcs, MasksEqualRaytraceOnQuad) {
  expect_equal_masks(compare_masks(make_test_frame("quad", 64, 64, grid_samples(16))));
}

TEST(Dcs, MasksEqualRaytraceOnSpheres) {
  expect_equal_masks(compare_masks(make_test_frame("spheres", 48, 48, grid_samples(16))));
}

/// Neighbouring silhouette edges' covered sectors meet on the ray from the light centre through
/// their shared vertex. A sample exactly on it (h = 0 in float) must be crossed by exactly one of
/// the two edges, whichever way each is stored: counting it in both put a spheres sample off by 2
/// (one edge's multiplicity) in the -O1 build, where the float rounding of the ray landed on it.
TEST(Dcs, SampleOnTheRayThroughASharedVertexIsCoveredOnce) {
  // c = (0.5, 0.5), shared vertex v = (0.75, 0.75): the sample (0.875, 0.875) lies on the ray c → v
  // (h = 0 exactly) and beyond both edges' lines (x = 0.75 and y = 0.75).
  const DVec2 a(0.75, 0.25), v(0.75, 0.75), d(0.25, 0.75);
  const float u[1] = {0.875f}, w[1] = {0.875f};
  const auto covers = [&](const DVec2& from, const DVec2& to) {
    dcs::CoveredRegion r;
    int turn = 0;
    EXPECT_TRUE(dcs::covered_region(from, to, r, turn));
    int16_t counter = 0;
    return dcs::apply_region(&counter, u, w, 1, r, 1);
  };
  for (const bool first_reversed : {false, true})
    for (const bool second_reversed : {false, true}) {
      const int first = first_reversed ? covers(v, a) : covers(a, v);
      const int second = second_reversed ? covers(d, v) : covers(v, d);
      EXPECT_EQ(first + second, 1) << first_reversed << second_reversed;
    }
  // Off the ray the sectors do not overlap either: a sample just past it is in the second only.
  const float u2[1] = {0.874f}, w2[1] = {0.876f};
  dcs::CoveredRegion r1, r2;
  int turn = 0;
  dcs::covered_region(a, v, r1, turn);
  dcs::covered_region(v, d, r2, turn);
  int16_t c1 = 0, c2 = 0;
  EXPECT_EQ(dcs::apply_region(&c1, u2, w2, 1, r1, 1), 0);
  EXPECT_EQ(dcs::apply_region(&c2, u2, w2, 1, r2, 1), 1);
}

/// The default scene's box, sphere and fence panel (alpha removed; with alpha=opaque `dcs` counts
/// alpha-textured triangles as opaque, and says so in its counters; the perforated fence through
/// its soft textured shadow volumes: tests/test_stsv.cpp).
TEST(Dcs, MasksEqualRaytraceOnDefaultWithoutAlpha) {
  const auto t =
      make_test_frame(test::without_alpha(make_builtin_scene("default")), 48, 48, grid_samples(8));
  expect_equal_masks(compare_masks(t));
  const auto with_alpha = make_test_frame("default", 16, 16, grid_samples(2));
  EXPECT_GT(with_alpha.run("dcs", {{"alpha", "opaque"}})
                .per_light[0]
                .counters.at("alpha_textured_as_opaque"),
            0.0);
  EXPECT_EQ(with_alpha.run("dcs").per_light[0].counters.at("alpha_textured_as_opaque"), 0.0);
}

/// Open (holes), inconsistently wound (a third flipped) and non-manifold (a fin of three triangles
/// on one edge): exact through the per-receiver multiplicities, no solid heuristic.
TEST(Dcs, MasksEqualRaytraceOnOpenFlippedNonManifoldMesh) {
  expect_equal_masks(
      compare_masks(make_test_frame(test::open_non_manifold_scene(), 48, 48, grid_samples(8))));
}

/// The centre count from the light-facing half of closed meshes plus winding numbers
/// (wedges/dcs_init.hpp): camera and light inside a closed box around the scene (w = 1 at both),
/// and the light alone inside a closed box (w(c) = 1, the camera outside: everything outside dark).
TEST(Dcs, MasksEqualRaytraceWithClosedMeshesAroundCameraOrLight) {
  Scene room = make_builtin_scene("spheres");
  room.meshes.push_back(make_box(Vec3(0.0f, 2.5f, 0.0f), Vec3(7.0f, 3.2f, 7.0f)));
  room.meshes.back().material = room.meshes[0].material;
  expect_equal_masks(compare_masks(make_test_frame(std::move(room), 32, 32, grid_samples(8))), 50);
  Scene lantern = make_builtin_scene("spheres");
  const Light& l = lantern.lights[0];
  lantern.meshes.push_back(make_box(l.center, Vec3(0.9f, 0.3f, 0.9f)));
  lantern.meshes.back().material = lantern.meshes[0].material;
  const auto t = make_test_frame(std::move(lantern), 32, 32, grid_samples(4));
  const MethodResult d = t.run("dcs");
  double lit = 0.0;
  for (size_t i = 0; i < d.per_light[0].lit.size(); ++i)
    if (t.frame->receivers(0)[i] == kActive) lit += d.per_light[0].lit[i];
  EXPECT_EQ(lit, 0.0);
  expect_equal_masks(compare_masks(t), 50);
}

TEST(Dcs, MasksEqualRaytraceForDiskAndSphereLights) {
  for (LightShape shape : {LightShape::disk, LightShape::sphere}) {
    Scene scene = make_builtin_scene("spheres");
    Light& l = scene.lights[0];
    l.shape = shape;
    l.radius = 0.4f;
    l.normal = Vec3(0, -1, 0);
    expect_equal_masks(compare_masks(make_test_frame(std::move(scene), 40, 40, grid_samples(8))));
  }
}

TEST(Dcs, MasksEqualRaytraceForEverySampleCount) {
  for (int k : {4, 8, 32})
    expect_equal_masks(compare_masks(make_test_frame("spheres", k == 32 ? 24 : 40,
                                                     k == 32 ? 24 : 40, grid_samples(k))),
                       k == 4 ? 20 : 100);
}

TEST(Dcs, MasksEqualRaytraceForIrregularPatterns) {
  for (SamplePattern p :
       {SamplePattern::stratified, SamplePattern::decorrelated, SamplePattern::interleaved,
        SamplePattern::halton, SamplePattern::poisson})
    expect_equal_masks(compare_masks(make_test_frame("spheres", 32, 32, pattern(p, 8))));
}

TEST(Dcs, MasksEqualGears) {
  const auto t = make_test_frame("spheres", 40, 40, grid_samples(16));
  expect_equal_masks(test::compare_masks(t, "dcs", {}, true, "gears"));
}

/// Both wedge constructions bound the same regions: only the work changes, never the answer.
TEST(Dcs, WedgeConstructionDoesNotChangeTheAnswer) {
  const auto t = make_test_frame("spheres", 40, 40, grid_samples(8));
  const MethodResult paper = t.run("dcs", {}, true);
  const MethodResult hull = t.run("dcs", {{"construction", "hull"}}, true);
  EXPECT_EQ(paper.per_light[0].lit.pixels(), hull.per_light[0].lit.pixels());
}

/// The point-light limit: the centre count alone, i.e. `shadow_volume`.
TEST(Dcs, PointLightEqualsShadowVolume) {
  Scene scene = make_builtin_scene("spheres");
  scene.lights[0].shape = LightShape::point;
  const auto t = make_test_frame(std::move(scene), 64, 64, grid_samples(2));
  const MethodResult d = t.run("dcs");
  const MethodResult sv = t.run("shadow_volume");
  EXPECT_EQ(d.per_light[0].lit.pixels(), sv.per_light[0].lit.pixels());
  EXPECT_EQ(d.per_light[0].counters.at("wedges"), 0.0);
}

/// Fig. 4.3a: silhouettes from the light centre miss the edges that are silhouettes only from
/// part of a large light. A sphere close under a large light: its centre silhouette is a much
/// smaller loop than the light's.
TEST(Dcs, CentreSilhouettesUnderestimateThePenumbra) {
  Scene scene = make_builtin_scene("spheres");
  scene.meshes.resize(1);  // ground
  scene.meshes.push_back(make_sphere(Vec3(0.0f, 1.6f, 0.0f), 0.5f, 12, 24));
  scene.meshes.back().material = scene.meshes[0].material;
  scene.lights[0] = make_builtin_scene("quad").lights[0];
  scene.lights[0].center = Vec3(0.0f, 2.4f, 0.0f);
  scene.lights[0].edge_u = Vec3(0, 0, 2.0f);
  scene.lights[0].edge_v = Vec3(2.0f, 0, 0);
  const auto t = make_test_frame(std::move(scene), 48, 48, grid_samples(8));
  const MethodResult ex = t.run("exact");
  const MethodResult rt = t.run("raytrace");
  const MethodResult light = t.run("dcs");
  const MethodResult centre = t.run("dcs", {{"silhouettes", "centre"}});
  const Image<float>& e = ex.per_light[0].lit;
  const VDiff light_vs_exact = v_diff(t, e, light.per_light[0].lit);
  const VDiff centre_vs_exact = v_diff(t, e, centre.per_light[0].lit);
  const VDiff light_vs_rt = v_diff(t, rt.per_light[0].lit, light.per_light[0].lit);
  const VDiff centre_vs_rt = v_diff(t, rt.per_light[0].lit, centre.per_light[0].lit);
  std::printf(
      "vs exact: light %.4f (max %.3f), centre %.4f (max %.3f); vs raytrace: light %.2e, "
      "centre %.4f; silhouette edges light %.0f centre %.0f\n",
      light_vs_exact.mean, light_vs_exact.max, centre_vs_exact.mean, centre_vs_exact.max,
      light_vs_rt.mean, centre_vs_rt.mean, light.per_light[0].counters.at("silhouette_edges"),
      centre.per_light[0].counters.at("silhouette_edges"));
  EXPECT_LE(light_vs_rt.mean, 1e-4);
  EXPECT_GT(centre_vs_rt.mean, 0.01);
  EXPECT_GT(centre_vs_exact.mean, 3.0 * light_vs_exact.mean);
}

/// Eq. 4.2: per-sample emission weights, RGB, identical to raytrace's on the same samples.
TEST(Dcs, TexturedLightRgbEqualsRaytrace) {
  const auto t = make_test_frame(test::with_textured_light(make_builtin_scene("spheres")), 40, 40,
                                 grid_samples(8));
  const MethodResult rt = t.run("raytrace");
  const MethodResult d = t.run("dcs");
  ASSERT_TRUE(d.per_light[0].lit_rgb.has_value());
  double max_rgb = 0.0;
  int partial = 0;
  for (size_t i = 0; i < rt.per_light[0].lit.size(); ++i) {
    if (t.frame->receivers(0)[i] != kActive) continue;
    const Vec3 a = (*rt.per_light[0].lit_rgb)[i], b = (*d.per_light[0].lit_rgb)[i];
    for (int c = 0; c < 3; ++c) max_rgb = std::max(max_rgb, std::abs(double(a[c]) - b[c]));
    partial += a.x > 0.01f && a.x < 0.99f;
  }
  EXPECT_GT(partial, 50);
  EXPECT_LE(max_rgb, 1e-5);
  EXPECT_LE(v_diff(t, rt.per_light[0].lit, d.per_light[0].lit).max, 1e-5);
}

/// Eq. 4.6: `--shading integrate` sums the per-sample radiance of the unblocked samples; with
/// dcs's masks the image is raytrace's.
TEST(Dcs, IntegrateShadingEqualsRaytrace) {
  const auto t = make_test_frame(test::with_textured_light(make_builtin_scene("spheres")), 32, 32,
                                 grid_samples(8));
  const MethodResult rt = t.run("raytrace", {}, true);
  const MethodResult d = t.run("dcs", {}, true);
  const Image<Vec3> a = shade(*t.frame, {&rt.per_light[0]}, ShadingMode::integrate);
  const Image<Vec3> b = shade(*t.frame, {&d.per_light[0]}, ShadingMode::integrate);
  const Image<Vec3> m = shade(*t.frame, {&d.per_light[0]}, ShadingMode::modulate);
  double max_diff = 0.0, modulate_diff = 0.0;
  for (size_t i = 0; i < a.size(); ++i)
    for (int c = 0; c < 3; ++c) {
      max_diff = std::max(max_diff, std::abs(double(a[i][c]) - b[i][c]));
      modulate_diff = std::max(modulate_diff, std::abs(double(a[i][c]) - m[i][c]));
    }
  EXPECT_LE(max_diff, 1e-6);
  EXPECT_GT(modulate_diff, 1e-3);  // the per-sample integration is not the modulated image
}

Scene semi_opaque(Scene scene, float transmittance) {
  Material glass;
  glass.name = "glass";
  glass.transmittance = transmittance;
  scene.materials.push_back(glass);
  for (Mesh& m : scene.meshes)
    if (m.name != "ground") m.material = static_cast<int>(scene.materials.size() - 1);
  return scene;
}

/// §4.3.3 with one layer (the quad): the exact product and the paper's approximation agree, and
/// both equal raytrace on the same samples and `exact` up to the sampling error.
TEST(Dcs, SemiOpaqueOneLayerMatchesExact) {
  const auto t =
      make_test_frame(semi_opaque(make_builtin_scene("quad"), 0.5f), 40, 40, grid_samples(32));
  const MethodResult ex = t.run("exact");
  const MethodResult rt = t.run("raytrace");
  const MethodResult product = t.run("dcs");
  const MethodResult paper = t.run("dcs", {{"semi_opaque", "paper"}});
  const VDiff vs_rt = v_diff(t, rt.per_light[0].lit, product.per_light[0].lit);
  const VDiff vs_exact = v_diff(t, ex.per_light[0].lit, product.per_light[0].lit);
  const VDiff paper_vs_product = v_diff(t, product.per_light[0].lit, paper.per_light[0].lit);
  std::printf(
      "semi-opaque quad: vs raytrace %.2e, vs exact %.2e (max %.3f), paper vs product %.2e\n",
      vs_rt.mean, vs_exact.mean, vs_exact.max, paper_vs_product.mean);
  EXPECT_LE(vs_rt.max, 1e-5);
  EXPECT_LE(vs_exact.mean, 1e-3);
  EXPECT_LE(paper_vs_product.max, 1e-6);
}

/// Closed semi-opaque spheres: two crossings per sphere. The exact product equals raytrace; the
/// paper's sum of opaqueness saturates (2 × (1 − 0.5) = 1: dark where the product gives 1/4).
TEST(Dcs, SemiOpaqueSpheresProductEqualsRaytracePaperIsDarker) {
  const auto t =
      make_test_frame(semi_opaque(make_builtin_scene("spheres"), 0.5f), 40, 40, grid_samples(8));
  const MethodResult rt = t.run("raytrace");
  const MethodResult product = t.run("dcs");
  const MethodResult paper = t.run("dcs", {{"semi_opaque", "paper"}});
  const VDiff vs_rt = v_diff(t, rt.per_light[0].lit, product.per_light[0].lit);
  const VDiff paper_vs_rt = v_diff(t, rt.per_light[0].lit, paper.per_light[0].lit);
  std::printf("semi-opaque spheres: product vs raytrace %.2e, paper vs raytrace %.4f (max %.3f)\n",
              vs_rt.mean, paper_vs_rt.mean, paper_vs_rt.max);
  EXPECT_LE(vs_rt.mean, 1e-4);
  EXPECT_GT(paper_vs_rt.mean, 0.02);
  EXPECT_GE(paper_vs_rt.max, 0.2);
}

TEST(Dcs, MasksEqualRaytraceOnBunny) {
  if (!find_model("bunny00.off")) GTEST_SKIP() << "bunny not fetched: run scripts/fetch-models.sh";
  // Classification brute-forces 70k triangles per mismatch: only count here.
  const MaskAgreement a =
      compare_masks(make_test_frame("bunny", 40, 40, grid_samples(16)), {}, false);
  std::printf("bunny masks: %llu pairs, %d blocked, %llu differ\n",
              static_cast<unsigned long long>(a.pairs), a.blocked,
              static_cast<unsigned long long>(a.differ));
  EXPECT_GT(a.blocked, 1000);
  EXPECT_LE(static_cast<double>(a.differ), 1e-3 * a.pairs) << a.differ << " of " << a.pairs;
  EXPECT_LE(a.mean_abs_dv, 1e-3);
}

TEST(Dcs, MasksEqualRaytraceOnDragon) {
  if (!find_model("ChineseDragon-10kv.off"))
    GTEST_SKIP() << "dragon not fetched: run scripts/fetch-models.sh";
  const MaskAgreement a =
      compare_masks(make_test_frame("dragon", 40, 40, grid_samples(8)), {}, false);
  EXPECT_GT(a.blocked, 500);
  EXPECT_LE(static_cast<double>(a.differ), 1e-3 * a.pairs) << a.differ << " of " << a.pairs;
  EXPECT_LE(a.mean_abs_dv, 1e-3);
}

TEST(Dcs, ReportsStagesAndCounters) {
  const auto t = make_test_frame("spheres", 32, 32, grid_samples(8));
  const Visibility v = t.run("dcs").per_light[0];
  for (const char* key :
       {"silhouette_edges", "straddling_edges", "wedges", "edges_per_penumbra_pixel",
        "covered_updates_per_pixel", "counter_min", "counter_max", "umbra_early_outs"})
    EXPECT_TRUE(v.counters.count(key)) << key;
  EXPECT_GT(v.counters.at("covered_sample_updates"), 0.0);
  EXPECT_GE(v.counters.at("counter_min"), 0.0);  // a depth complexity is never negative
  EXPECT_GE(v.counters.at("counter_max"), 2.0);  // closed spheres: two crossings each
  for (const char* stage : {"setup", "silhouettes", "init", "wedges", "sampling"})
    EXPECT_GT(v.times.get(stage), 0.0) << stage;
}

}  // namespace
}  // namespace penumbra
