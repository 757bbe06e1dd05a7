// The two references against each other and against closed forms, on whole frames
// (G-buffer → receivers → method), as the CLI runs them.
#include <gtest/gtest.h>

#include <cmath>

#include "penumbra/render/receivers.hpp"
#include "penumbra/scene/model_paths.hpp"
#include "penumbra/scene/shapes.hpp"
#include "support/frame_helpers.hpp"

namespace penumbra {
namespace {

using test::make_test_frame;

LightSampleSpec stratified(int k) {
  LightSampleSpec s;
  s.pattern = SamplePattern::stratified;
  s.k = k;
  s.seed = 7;
  return s;
}

/// Pixels of the quad scene's ground: their exact answer is the closed form.
TEST(References, ExactMatchesClosedFormOnQuadGround) {
  const auto t = make_test_frame("quad", 64, 64, stratified(1));
  const MethodResult exact = t.run("exact");
  const GBuffer& g = t.frame->gbuffer();
  int checked = 0;
  for (size_t i = 0; i < g.pixel_count(); ++i) {
    if (g.is_background(i) || t.scene->meshes[g.mesh_id[i]].name != "ground") continue;
    const Vec3 p = g.shadow_origin(i);
    EXPECT_NEAR(exact.per_light[0].lit[i], quad_scene_visible_fraction(p.x, p.y, p.z), 2e-5)
        << "pixel " << i;
    ++checked;
  }
  EXPECT_GT(checked, 1000);
}

TEST(References, RaytraceStratified32WithinHalfPercentOfExactOnQuad) {
  const auto t = make_test_frame("quad", 64, 64, stratified(32));
  const ErrorStats e = compare_results(*t.frame, t.run("exact"), t.run("raytrace"));
  EXPECT_LT(e.mean_abs, 0.005);
  EXPECT_GT(e.shadowed_pixels, 200u);
}

TEST(References, ExactAgreesWithRaytrace64OnSpheres) {
  const auto t = make_test_frame("spheres", 96, 96, stratified(64));
  const ErrorStats e = compare_results(*t.frame, t.run("exact"), t.run("raytrace"));
  EXPECT_LE(e.mean_abs_shadowed, 0.002);
  EXPECT_GT(e.shadowed_pixels, 500u);
}

TEST(References, ExactAgreesWithRaytrace64OnFence) {
  const auto t = make_test_frame("fence", 64, 64, stratified(64));
  const ErrorStats e = compare_results(*t.frame, t.run("exact"), t.run("raytrace"));
  EXPECT_LE(e.mean_abs_shadowed, 0.003);
  EXPECT_GT(e.shadowed_pixels, 300u);
}

TEST(References, ExactAgreesWithRaytrace64OnBunny) {
  if (!find_model("bunny00.off")) GTEST_SKIP() << "bunny not fetched: run scripts/fetch-models.sh";
  const auto t = make_test_frame("bunny", 48, 48, stratified(64));
  const ErrorStats e = compare_results(*t.frame, t.run("exact"), t.run("raytrace"));
  EXPECT_LE(e.mean_abs_shadowed, 0.002);
}

/// A point light: both references must give the single-ray hard shadow, which we compute here by
/// brute force over every triangle (no BVH, no Embree).
TEST(References, PointLightGivesHardShadowOfBruteForceSegmentTest) {
  Scene scene = make_builtin_scene("spheres");
  scene.lights[0].shape = LightShape::point;
  LightSampleSpec one;
  one.k = 1;
  const auto t = make_test_frame(std::move(scene), 48, 48, one);
  const MethodResult exact = t.run("exact");
  const MethodResult rt = t.run("raytrace");
  const GBuffer& g = t.frame->gbuffer();
  const Vec3 light = t.scene->lights[0].center;
  int shadowed = 0, differ_exact = 0, differ_rt = 0, active = 0;
  for (size_t i = 0; i < g.pixel_count(); ++i) {
    if (t.frame->receivers(0)[i] != kActive) continue;
    ++active;
    const DVec3 o = DVec3(g.shadow_origin(i)), d = DVec3(light) - o;
    bool blocked = false;
    for (const Mesh& m : t.scene->meshes)
      for (size_t tri = 0; tri < m.triangle_count() && !blocked; ++tri)
        blocked = test::segment_crosses_triangle(o, d, DVec3(m.vertex(tri, 0)),
                                                 DVec3(m.vertex(tri, 1)), DVec3(m.vertex(tri, 2)));
    shadowed += blocked;
    differ_exact += (exact.per_light[0].lit[i] < 0.5f) != blocked;
    differ_rt += (rt.per_light[0].lit[i] < 0.5f) != blocked;
    EXPECT_TRUE(exact.per_light[0].lit[i] == 0.0f || exact.per_light[0].lit[i] == 1.0f);
  }
  EXPECT_GT(shadowed, 100);
  // Numerically ambiguous pixels (rays grazing a shared edge) may differ: at most 0.1 %.
  EXPECT_LE(differ_exact, active / 1000);
  EXPECT_LE(differ_rt, active / 1000);
}

TEST(References, RaytraceMasksCountMatchesVisibleFraction) {
  const auto t = make_test_frame("quad", 32, 32, stratified(8));
  const MethodResult rt = t.run("raytrace", {}, true);
  const Visibility& v = rt.per_light[0];
  ASSERT_TRUE(v.masks.has_value());
  for (size_t i = 0; i < v.lit.size(); ++i) {
    if (t.frame->receivers(0)[i] != kActive) continue;
    int blocked = 0;
    for (int s = 0; s < 64; ++s) blocked += v.masks->blocked(i, s);
    EXPECT_FLOAT_EQ(v.lit[i], 1.0f - static_cast<float>(blocked) / 64.0f);
  }
}

TEST(References, SingleRayPathEqualsPacketPath) {
  const auto t = make_test_frame("fence", 48, 48, stratified(8));
  const MethodResult packets = t.run("raytrace", {{"path", "packet16"}});
  const MethodResult single = t.run("raytrace", {{"path", "single"}});
  EXPECT_EQ(packets.per_light[0].lit.pixels(), single.per_light[0].lit.pixels());
}

TEST(References, SemiOpaqueOccluderHalvesTheLight) {
  Scene scene = make_builtin_scene("quad");
  Material glass;
  glass.name = "glass";
  glass.transmittance = 0.5f;
  scene.materials.push_back(glass);
  scene.meshes[1].material = static_cast<int>(scene.materials.size() - 1);
  const auto t = make_test_frame(std::move(scene), 48, 48, stratified(16));
  const MethodResult exact = t.run("exact");
  const MethodResult rt = t.run("raytrace");
  // Embree calls a filter several times per hit in packet traversal: both paths must agree.
  EXPECT_EQ(rt.per_light[0].lit.pixels(),
            t.run("raytrace", {{"path", "single"}}).per_light[0].lit.pixels());
  const GBuffer& g = t.frame->gbuffer();
  int umbra = 0;
  for (size_t i = 0; i < g.pixel_count(); ++i) {
    if (g.is_background(i) || t.scene->meshes[g.mesh_id[i]].name != "ground") continue;
    const Vec3 p = g.shadow_origin(i);
    const double closed = quad_scene_visible_fraction(p.x, p.y, p.z);
    // Covered part of the light passes half: V = 1 − 0.5 · covered.
    EXPECT_NEAR(exact.per_light[0].lit[i], 1.0 - 0.5 * (1.0 - closed), 2e-5);
    if (closed == 0.0) {
      ++umbra;
      EXPECT_NEAR(rt.per_light[0].lit[i], 0.5f, 1e-6);
    }
  }
  EXPECT_GT(umbra, 20);
}

TEST(Frame, BackgroundIsLitAndBackFacingIsDark) {
  Scene scene = make_builtin_scene("quad");
  scene.lights[0].center.y = -3.0f;  // below the ground: every ground pixel faces away
  scene.lights[0].edge_v = -scene.lights[0].edge_v;
  scene.camera.position = Vec3(0.0f, 0.5f, 2.0f);  // sees the sky above the horizon too
  scene.camera.target = Vec3(0.0f);
  const auto t = make_test_frame(std::move(scene), 32, 32, stratified(2));
  const MethodResult rt = t.run("raytrace");
  const GBuffer& g = t.frame->gbuffer();
  int background = 0;
  for (size_t i = 0; i < g.pixel_count(); ++i) {
    if (g.is_background(i)) {
      ++background;
      EXPECT_EQ(rt.per_light[0].lit[i], 1.0f);
    } else if (t.scene->meshes[g.mesh_id[i]].name == "ground") {
      EXPECT_EQ(t.frame->receivers(0)[i], kBackFacing);
      EXPECT_EQ(rt.per_light[0].lit[i], 0.0f);
    }
  }
  EXPECT_GT(background, 0);
}

TEST(GBuffer, CentrePixelHitsTheGroundWhereTheCameraLooks) {
  Scene scene = make_builtin_scene("quad");
  scene.meshes.erase(scene.meshes.begin() + 1);  // only the ground
  scene.camera.position = Vec3(0.0f, 0.5f, 2.0f);
  scene.camera.target = Vec3(0.0f, 0.0f, 0.0f);
  const auto t = make_test_frame(std::move(scene), 31, 31, stratified(1));
  const GBuffer& g = t.frame->gbuffer();
  const size_t centre = 15 * 31 + 15;
  EXPECT_NEAR(g.world_pos[centre].x, 0.0f, 1e-5f);
  EXPECT_NEAR(g.world_pos[centre].y, 0.0f, 1e-6f);
  EXPECT_NEAR(g.world_pos[centre].z, 0.0f, 1e-5f);
  EXPECT_NEAR(g.depth[centre], std::sqrt(4.25f), 1e-5f);
  EXPECT_NEAR(g.geo_normal[centre].y, 1.0f, 1e-6f);
  EXPECT_EQ(g.mesh_id[centre], 0);
  // The offset is relative to the hit triangle: the ground quad's largest |coordinate|.
  const Bounds3 ground = t.scene->meshes[0].bounds();
  const float ground_magnitude = std::max({-ground.lo.x, -ground.lo.z, ground.hi.x, ground.hi.z});
  EXPECT_FLOAT_EQ(g.ray_offset[centre], kRayOffsetRelative * ground_magnitude);
  EXPECT_TRUE(g.is_background(0));  // the top-left corner looks above the horizon
}

}  // namespace
}  // namespace penumbra
