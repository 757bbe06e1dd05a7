// `silhouette_map` (Valient & Bujnak, Valient 2005 §2): the TAM and the silhouette-pass geometry in
// isolation (eq. 1, eq. 2, the §2.1.1 degenerate correction), then whole frames: hard mode against
// shadow_volume (anti-aliased boundary vs plain shadow_map at the same resolution), soft mode
// against exact next to pcss, and degenerate input (zero-area faces, open meshes): no NaN.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstring>

#include "penumbra/render/receivers.hpp"
#include "penumbra/scene/model_paths.hpp"
#include "penumbra/scene/shapes.hpp"
#include "penumbra/shadows/depth_maps/silhouette_map.hpp"
#include "support/frame_helpers.hpp"

namespace penumbra {
namespace {

using test::centre_sample;
using test::make_test_frame;
using test::TestFrame;

LightSampleSpec pcss_samples() {
  LightSampleSpec s;
  s.pattern = SamplePattern::grid;
  s.k = 4;
  return s;
}

MethodResult run_silmap(const TestFrame& t, const std::map<std::string, std::string>& options) {
  const MethodInfo info = silmap::silhouette_map_info();
  MethodResult r = t.frame->run(info, resolve_options(info, options), false);
  for (float v : r.per_light[0].lit.pixels()) EXPECT_TRUE(std::isfinite(v) && v >= 0 && v <= 1);
  return r;
}

double inradius(const DVec3 s[3]) {
  double cx, cy, r;
  silmap::incircle(s, cx, cy, r);
  return r;
}

TEST(SilhouetteMapGeometry, ScaleFactorEq2) {
  // w_o = 2, width 3: w_s = 3 + 2√2, w_sc = w_s / 2.
  EXPECT_NEAR(silmap::scale_factor(2.0, 3.0), (2.0 + 0.5 * (3.0 + 2.0 * std::sqrt(2.0))) / 2.0,
              1e-12);
}

TEST(SilhouetteMapGeometry, IncircleOfRightTriangle) {
  const DVec3 s[3] = {{0, 0, 1}, {3, 0, 1}, {0, 4, 1}};
  double cx, cy, r;
  silmap::incircle(s, cx, cy, r);
  EXPECT_NEAR(r, 1.0, 1e-12);  // (3 + 4 − 5) / 2
  EXPECT_NEAR(cx, 1.0, 1e-12);
  EXPECT_NEAR(cy, 1.0, 1e-12);
}

TEST(SilhouetteMapGeometry, DegenerateAfterProjectionIsCorrected) {
  const double half_diag = 0.5 * std::sqrt(2.0);
  DVec3 collinear[3] = {{0, 0, 1}, {10, 0, 1}, {4, 0, 1}};  // edge-on face
  EXPECT_TRUE(silmap::correct_degenerate(collinear));
  EXPECT_GE(inradius(collinear), half_diag);
  EXPECT_EQ(collinear[0], DVec3(0, 0, 1));  // the longest edge stays
  EXPECT_EQ(collinear[1], DVec3(10, 0, 1));
  DVec3 point[3] = {{5, 5, 1}, {5, 5, 1}, {5, 5, 1}};  // zero area, one point
  EXPECT_TRUE(silmap::correct_degenerate(point));
  EXPECT_GE(inradius(point), half_diag);
  DVec3 sliver[3] = {{0, 0, 1}, {20, 0, 1}, {10, 0.05, 1}};
  EXPECT_TRUE(silmap::correct_degenerate(sliver));
  EXPECT_GE(inradius(sliver), half_diag);
  EXPECT_GT(sliver[2].y, 0.05);  // moved away from the opposite edge
  DVec3 fine[3] = {{0, 0, 1}, {10, 0, 1}, {0, 10, 1}};
  EXPECT_FALSE(silmap::correct_degenerate(fine));
}

/// An open mesh (one quad = two triangles): its four border edges get −n_f and are silhouettes
/// from any point off its plane; the shared diagonal is not. A zero-area face is left out.
TEST(SilhouetteMapGeometry, TamOpenEdgesAndZeroAreaFaces) {
  Scene s;
  Mesh quad = make_quad(Vec3(0, 1, 0), Vec3(1, 0, 0), Vec3(0, 0, 1));
  const uint32_t a = quad.triangles[0].v[0];
  quad.triangles.push_back({{a, a, quad.triangles[0].v[1]}});  // zero area
  s.meshes.push_back(quad);
  const std::vector<silmap::TamFace> tam = silmap::build_tam(s);
  ASSERT_EQ(tam.size(), 2u);
  int silhouettes = 0, negated = 0;
  for (const silmap::TamFace& f : tam)
    for (int c = 0; c < 3; ++c) {
      silhouettes += silmap::is_silhouette(f, c, DVec3(0.2, 3.0, 0.1));
      negated += f.adjacent[c] == -f.normal;
    }
  EXPECT_EQ(negated, 4);
  EXPECT_EQ(silhouettes, 4);
}

/// Hard-shadow boundary pixels: active pixels whose shadow_volume value differs from a 4-neighbour.
struct BoundaryError {
  double silmap = 0.0, shadow_map = 0.0;
  double silmap_all = 0.0, shadow_map_all = 0.0;
  int pixels = 0;
};

BoundaryError boundary_error(const TestFrame& t, int resolution, const char* aa_width) {
  const std::string res = std::to_string(resolution);
  const MethodResult sv = t.run("shadow_volume");
  const MethodResult sm = t.run("shadow_map", {{"resolution", res}});
  const MethodResult hm =
      run_silmap(t, {{"resolution", res}, {"mode", "hard"}, {"aa_width", aa_width}});
  const Image<uint8_t>& rc = t.frame->receivers(0);
  const Image<float>& ref = sv.per_light[0].lit;
  BoundaryError e;
  int active = 0;
  for (int y = 0; y < ref.height(); ++y)
    for (int x = 0; x < ref.width(); ++x) {
      const size_t i = static_cast<size_t>(y) * ref.width() + x;
      if (rc[i] != kActive) continue;
      ++active;
      const double es = std::abs(hm.per_light[0].lit[i] - ref[i]);
      const double em = std::abs(sm.per_light[0].lit[i] - ref[i]);
      e.silmap_all += es;
      e.shadow_map_all += em;
      bool edge = false;
      const int dx[4] = {1, -1, 0, 0}, dy[4] = {0, 0, 1, -1};
      for (int k = 0; k < 4; ++k) {
        const int u = x + dx[k], v = y + dy[k];
        if (u < 0 || v < 0 || u >= ref.width() || v >= ref.height()) continue;
        const size_t j = static_cast<size_t>(v) * ref.width() + u;
        edge = edge || (rc[j] == kActive && ref[j] != ref[i]);
      }
      if (!edge) continue;
      ++e.pixels;
      e.silmap += es;
      e.shadow_map += em;
    }
  if (e.pixels > 0) {
    e.silmap /= e.pixels;
    e.shadow_map /= e.pixels;
  }
  e.silmap_all /= std::max(1, active);
  e.shadow_map_all /= std::max(1, active);
  std::printf(
      "    map %d, aa_width %s: %d boundary px, mean|V-V_sv| silhouette_map %.4f "
      "shadow_map %.4f; all active px %.5f vs %.5f\n",
      resolution, aa_width, e.pixels, e.silmap, e.shadow_map, e.silmap_all, e.shadow_map_all);
  return e;
}

Scene point_lit(const std::string& name) {
  Scene s = make_builtin_scene(name);
  s.lights[0].shape = LightShape::point;
  return s;
}

/// The quad's straight edges: with a step table (aa_width 0) the reconstructed edge lies within a
/// small fraction of a texel of the exact one; with the default 1-texel ramp the error against the
/// binary reference is the ramp itself (≈ ramp/4 per boundary pixel), still below shadow_map's
/// staircase at coarse maps.
TEST(SilhouetteMapHard, BoundaryCloserThanShadowMapOnQuad) {
  const TestFrame t = make_test_frame(point_lit("quad"), 96, 96, centre_sample());
  for (int res : {32, 64}) {
    const BoundaryError e = boundary_error(t, res, "0");
    EXPECT_GT(e.pixels, 50);
    EXPECT_LT(e.silmap, 0.25);
    EXPECT_LT(e.silmap, 0.5 * e.shadow_map);
    EXPECT_LT(e.silmap_all, e.shadow_map_all);
    const BoundaryError ramp = boundary_error(t, res, "1");
    EXPECT_LT(ramp.silmap, ramp.shadow_map);
  }
}

/// 27 small spheres whose silhouettes overlap in the light's view ("touched silhouettes", §2.2.1):
/// better than shadow_map once a sphere spans ~20 texels (map 512); at coarser maps the nearest
/// silhouette often belongs to another sphere and silhouette_map is worse (docs: artefacts).
TEST(SilhouetteMapHard, BoundaryCloserThanShadowMapOnSpheres) {
  const TestFrame t = make_test_frame(point_lit("spheres"), 96, 96, centre_sample());
  const BoundaryError e = boundary_error(t, 512, "0");
  EXPECT_GT(e.pixels, 200);
  EXPECT_LT(e.silmap, e.shadow_map);
  EXPECT_LT(e.silmap_all, e.shadow_map_all);
  boundary_error(t, 128, "0");  // reported only
}

/// Soft mode for a small spherical light: mean |error| vs exact over the active pixels, reported
/// next to pcss and the hard shadow_map.
void soft_vs_exact(Scene s, const char* label, double radius, double measured_soft) {
  s.lights[0].shape = LightShape::sphere;
  s.lights[0].radius = static_cast<float>(radius);
  const TestFrame t = make_test_frame(std::move(s), 96, 96, pcss_samples());
  const MethodResult exact = t.run("exact");
  const Image<uint8_t>& rc = t.frame->receivers(0);
  Image<float> mask(rc.width(), rc.height(), 0.0f);
  for (size_t i = 0; i < rc.size(); ++i) mask.pixels()[i] = rc.pixels()[i] == kActive ? 1.0f : 0.0f;
  auto err = [&](const MethodResult& r) {
    return compare_images(exact.per_light[0].lit, r.per_light[0].lit, &mask);
  };
  const ErrorStats soft = err(run_silmap(t, {{"resolution", "256"}, {"mode", "soft"}}));
  const ErrorStats hard = err(run_silmap(t, {{"resolution", "256"}, {"mode", "hard"}}));
  const ErrorStats pcss = err(t.run("pcss", {{"resolution", "256"}}));
  const ErrorStats sm = err(t.run("shadow_map", {{"resolution", "256"}}));
  std::printf(
      "    %s, sphere r=%.2f, map 256: mean|err| (shadowed) silhouette_map soft %.5f (%.4f), "
      "hard %.5f (%.4f), pcss %.5f (%.4f), shadow_map %.5f (%.4f)\n",
      label, radius, soft.mean_abs, soft.mean_abs_shadowed, hard.mean_abs, hard.mean_abs_shadowed,
      pcss.mean_abs, pcss.mean_abs_shadowed, sm.mean_abs, sm.mean_abs_shadowed);
  // Soft mode must beat its own hard mode; against the hard shadow map it wins on spheres (0.0263
  // against 0.0328) and loses by 4 % on bunny (0.01038 against 0.00998, the model's own
  // terminator); it is not claimed to beat pcss (docs). Its measured error is held within 5 %: a
  // soft mode that only blurred or only hardened moves it more.
  EXPECT_LT(soft.mean_abs, hard.mean_abs);
  EXPECT_LT(soft.mean_abs, 1.05 * sm.mean_abs);
  EXPECT_NEAR(soft.mean_abs, measured_soft, 0.05 * measured_soft);
}

TEST(SilhouetteMapSoft, SmallSphereLightOnSpheres) {
  soft_vs_exact(make_builtin_scene("spheres"), "spheres", 0.1, 0.02635);
}

TEST(SilhouetteMapSoft, SmallSphereLightOnBunny) {
  if (!find_model("bunny00.off")) GTEST_SKIP() << "bunny not fetched: run scripts/fetch-models.sh";
  soft_vs_exact(make_builtin_scene("bunny"), "bunny", 0.1, 0.01038);
}

/// Open meshes (a sphere with holes and flipped faces, the negated-normal rule) and zero-area
/// faces in the silhouette pass: every value finite, in [0, 1], both modes.
TEST(SilhouetteMapDegenerate, OpenMeshAndZeroAreaFacesNoNaN) {
  Scene s = make_builtin_scene("quad");
  Mesh sphere = test::open_flipped_sphere();
  sphere.name = "open";
  sphere.material = 1;
  s.meshes[1] = sphere;
  s.lights[0].shape = LightShape::sphere;
  s.lights[0].radius = 0.1f;
  const TestFrame t = make_test_frame(std::move(s), 64, 64, centre_sample());
  for (const char* mode : {"hard", "soft"}) {
    const MethodResult r = run_silmap(t, {{"resolution", "64"}, {"mode", mode}});
    EXPECT_GT(r.per_light[0].counters.at("silhouette_faces"), 0.0);
  }
  // Zero-area faces straight into the silhouette pass (validate_scene would remove them).
  Scene z;
  Mesh m = make_quad(Vec3(0, 1, 0), Vec3(1, 0, 0), Vec3(0, 0, 1));
  const uint32_t a = m.triangles[0].v[0], b = m.triangles[0].v[1];
  m.triangles.push_back({{a, a, b}});
  m.positions.push_back(m.positions[a]);
  m.triangles.push_back({{a, static_cast<uint32_t>(m.positions.size() - 1), b}});
  z.meshes.push_back(m);
  const std::vector<silmap::TamFace> tam = silmap::build_tam(z);
  EXPECT_EQ(tam.size(), 2u);
  const Vec3 cover[2] = {Vec3(-1, 0, -1), Vec3(1, 0, 1)};
  DepthMapSpec spec;
  spec.resolution = 48;
  const DepthMap map = render_depth_map(z, Vec3(0, 3, 0), cover, spec);
  const silmap::SilhouetteLayer layer = silmap::render_silhouettes(tam, map, 1.5);
  int covered = 0;
  for (size_t i = 0; i < layer.distance.size(); ++i) {
    EXPECT_TRUE(std::isfinite(layer.distance.pixels()[i]));
    EXPECT_FALSE(std::isnan(layer.depth.pixels()[i]));
    covered += layer.depth.pixels()[i] < kInfinity;
  }
  EXPECT_GT(covered, 0);
}

/// The silhouette pass visits the texels of the thick silhouettes, not the faces' area: a stack of
/// large open triangles (every edge a silhouette), each covering 40 % of the map, costs its
/// silhouettes' length × band width per face. Visiting each scaled face whole (as once: ~5 ms a
/// face at 2048², 2 000 stacked triangles in 10 s) is over 13× the visits here.
TEST(SilhouetteMapCost, StackedFacesCostTheirSilhouettesNotTheirArea) {
  constexpr int kFaces = 100, kResolution = 512;
  Scene z;
  Mesh m;
  for (int k = 0; k < kFaces; ++k) {
    const float y = 1.0f + 1e-4f * static_cast<float>(k);
    const uint32_t base = static_cast<uint32_t>(m.positions.size());
    // (Within the map: it is fitted to the receivers of `cover` below, from the light.)
    m.positions.insert(m.positions.end(),
                       {Vec3(-0.6f, y, -0.6f), Vec3(0.6f, y, -0.6f), Vec3(-0.6f, y, 0.6f)});
    m.triangles.push_back({{base, base + 2, base + 1}});
  }
  z.meshes.push_back(m);
  const std::vector<silmap::TamFace> tam = silmap::build_tam(z);
  ASSERT_EQ(tam.size(), static_cast<size_t>(kFaces));
  const Vec3 cover[2] = {Vec3(-1, 0, -1), Vec3(1, 0, 1)};
  DepthMapSpec spec;
  spec.resolution = kResolution;
  const DepthMap map = render_depth_map(z, Vec3(0, 3, 0), cover, spec);
  const double half_band = 1.5;
  const silmap::SilhouetteLayer layer = silmap::render_silhouettes(tam, map, half_band);
  EXPECT_EQ(layer.silhouette_faces, static_cast<size_t>(kFaces));

  // One face on the map: its area and perimeter in texels.
  double sx[3], sy[3], z_unused;
  for (int c = 0; c < 3; ++c) ASSERT_TRUE(map.project(tam[0].p[c], sx[c], sy[c], z_unused));
  const double area =
      0.5 * std::abs((sx[1] - sx[0]) * (sy[2] - sy[0]) - (sy[1] - sy[0]) * (sx[2] - sx[0]));
  double perimeter = 0.0;
  for (int c = 0; c < 3; ++c)
    perimeter += std::hypot(sx[(c + 1) % 3] - sx[c], sy[(c + 1) % 3] - sy[c]);
  ASSERT_GT(area, 0.3 * kResolution * kResolution);
  for (int c = 0; c < 3; ++c)
    ASSERT_TRUE(sx[c] > 8 && sx[c] < kResolution - 8 && sy[c] > 8 && sy[c] < kResolution - 8);
  // Each edge's band: 2·(half_band + 1) texels across plus a texel of rounding, and its length
  // plus the capped ends.
  const double band_texels =
      perimeter * (2.0 * (half_band + 1.0) + 1.0) + 3.0 * std::pow(2.0 * (half_band + 2.0), 2.0);
  const double visited = static_cast<double>(layer.texels_visited);
  EXPECT_LE(visited, kFaces * band_texels);
  EXPECT_LT(visited, 0.1 * kFaces * area);
  // Measured 783 962: 7.4 % of the faces' area (a band of ~5 texels along 1 572 texels of edges).
  EXPECT_NEAR(visited, 783962, 0.02 * 783962);
  // And every texel of the thick silhouettes was written (the band along the three edges).
  int covered = 0;
  for (size_t i = 0; i < layer.depth.size(); ++i) covered += layer.depth.pixels()[i] < kInfinity;
  // Measured 5 997: 2·half_band·perimeter = 4 715 texels, widened by the stack (its faces' images
  // grow by 0.5 % from the lowest to the highest, ~3 texels at the far corners).
  EXPECT_NEAR(covered, 5997, 150);
}

/// Copies of one model in one place (5 000 instanced boxes) are left out of the silhouette pass:
/// the layer of 50 coincident copies equals the layer of one, texel for texel.
TEST(SilhouetteMapCost, CoincidentCopiesAreDrawnOnce) {
  const auto stack = [](int copies) {
    // One mesh per copy (copies welded into one mesh would make their shared edges non-manifold,
    // hence silhouettes).
    Scene z;
    for (int k = 0; k < copies; ++k) {
      Mesh m;
      m.positions = {Vec3(-0.5f, 1.0f, -0.5f), Vec3(0.5f, 1.0f, -0.5f), Vec3(-0.5f, 1.0f, 0.5f),
                     Vec3(0.5f, 1.0f, 0.5f)};
      m.triangles = {{{0, 2, 1}}, {{1, 2, 3}}};
      z.meshes.push_back(m);
    }
    return z;
  };
  const Vec3 cover[2] = {Vec3(-1, 0, -1), Vec3(1, 0, 1)};
  DepthMapSpec spec;
  spec.resolution = 128;
  const Scene one = stack(1), many = stack(50);
  const DepthMap map = render_depth_map(one, Vec3(0, 3, 0), cover, spec);
  const silmap::SilhouetteLayer a = silmap::render_silhouettes(silmap::build_tam(one), map, 1.5);
  const silmap::SilhouetteLayer b = silmap::render_silhouettes(silmap::build_tam(many), map, 1.5);
  EXPECT_EQ(a.duplicate_faces, 0u);
  EXPECT_EQ(b.duplicate_faces, 49u * 2u);
  EXPECT_EQ(a.texels_visited, b.texels_visited);
  ASSERT_EQ(a.depth.size(), b.depth.size());
  EXPECT_EQ(
      std::memcmp(a.depth.pixels().data(), b.depth.pixels().data(), a.depth.size() * sizeof(float)),
      0);
  EXPECT_EQ(std::memcmp(a.distance.pixels().data(), b.distance.pixels().data(),
                        a.distance.size() * sizeof(float)),
            0);
}

}  // namespace
}  // namespace penumbra
