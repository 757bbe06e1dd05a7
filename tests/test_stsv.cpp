// Soft textured shadow volumes [Forest 2008 ch. 5] in `dcs`, `wedges` and `wedge_blend`: the
// per-sample answer of `raytrace` through perforated triangles (dcs, and the wedge methods where
// only S-triangles occlude), the gain over solid perforated occluders, the overlap artifact of the
// wedge combination (fig. 5.4), fully transparent / opaque textures, both sides casting (§5.5) and
// semi-opaque textured occluders.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <functional>

#include "penumbra/render/receivers.hpp"
#include "penumbra/scene/alpha_mesh.hpp"
#include "penumbra/scene/shapes.hpp"
#include "support/frame_helpers.hpp"
#include "support/mask_agreement.hpp"

namespace penumbra {
namespace {

using test::compare_masks;
using test::expect_equal_masks;
using test::make_test_frame;
using test::MaskAgreement;
using test::TestFrame;

using test::grid_samples;

/// A measured figure held to within `rel` of itself.
void expect_measured(double got, double measured, double rel, const char* what) {
  std::printf("    %-44s %.6g (measured %.6g)\n", what, got, measured);
  EXPECT_NEAR(got, measured, rel * measured) << what;
}

/// |V − V_ref| over the active pixels the reference shadows (V_ref < 1 − 1e-4), and the signed
/// mean over `region` pixels (all shadowed ones when null).
struct Diff {
  double mean_abs_shadowed = 0.0, max_abs = 0.0, mean_signed = 0.0;
  int shadowed = 0;
};
Diff diff(const TestFrame& t, const MethodResult& a, const MethodResult& ref) {
  const Image<float>& va = a.per_light[0].lit;
  const Image<float>& vr = ref.per_light[0].lit;
  Diff d;
  for (size_t i = 0; i < va.size(); ++i) {
    if (t.frame->receivers(0)[i] != kActive) continue;
    const double e = static_cast<double>(va[i]) - vr[i];
    d.max_abs = std::max(d.max_abs, std::abs(e));
    if (!(vr[i] < 1.0f - 1e-4f)) continue;
    ++d.shadowed;
    d.mean_abs_shadowed += std::abs(e);
    d.mean_signed += e;
  }
  if (d.shadowed) d.mean_abs_shadowed /= d.shadowed, d.mean_signed /= d.shadowed;
  return d;
}

bool same_lit(const MethodResult& a, const MethodResult& b) {
  const Image<float>& va = a.per_light[0].lit;
  const Image<float>& vb = b.per_light[0].lit;
  for (size_t i = 0; i < va.size(); ++i)
    if (va[i] != vb[i]) return false;
  return true;
}

double counter(const MethodResult& r, const char* key) {
  return r.per_light[0].counters.at(key);
}

/// `fence` with its alpha texture replaced by alpha(x, y) over 64 × 64 texels.
Scene fence_with(const std::function<float(int, int)>& alpha) {
  Scene s = make_builtin_scene("fence");
  Texture& tex = s.textures[s.materials[s.meshes[1].material].alpha_texture];
  for (int y = 0; y < tex.height; ++y)
    for (int x = 0; x < tex.width; ++x) tex.texels[y * tex.width + x] = alpha(x, y);
  return s;
}

// ---------------------------------------------------------------------------------------------
// dcs: a covered opaque texel increments D [§5.2.2], so the masks are raytrace's.

TEST(Stsv, DcsMasksEqualRaytraceOnFence) {
  const auto t = make_test_frame("fence", 48, 48, grid_samples(16));
  const MaskAgreement a = compare_masks(t, "dcs");
  expect_equal_masks(a, 10000);
  // Measured: 0 of 589 824 differ (release). The solid fence (alpha=opaque) differs on ~10 %.
  EXPECT_LE(a.differ, 20u);
  const MaskAgreement solid = compare_masks(t, "dcs", {{"alpha", "opaque"}}, false);
  std::printf("    alpha=opaque: %llu of %llu differ\n",
              static_cast<unsigned long long>(solid.differ),
              static_cast<unsigned long long>(solid.pairs));
  EXPECT_GT(solid.differ, solid.pairs / 50);
  const MethodResult r = t.run("dcs");
  EXPECT_EQ(counter(r, "stsv_triangles"), 2.0);
  EXPECT_GT(counter(r, "stsv_sample_lookups"), counter(r, "stsv_blocked_samples"));
  EXPECT_GT(counter(r, "stsv_blocked_samples"), 0.0);
  EXPECT_EQ(counter(r, "alpha_textured_as_opaque"), 0.0);
  EXPECT_EQ(counter(t.run("dcs", {{"alpha", "opaque"}}), "alpha_textured_as_opaque"), 2.0);
}

TEST(Stsv, DcsMasksEqualRaytraceOnDefault) {
  const auto t = make_test_frame("default", 48, 48, grid_samples(8));
  const MaskAgreement a = compare_masks(t, "dcs");
  expect_equal_masks(a, 1000);
  EXPECT_LE(a.differ, 20u);
}

/// Round lights (their light frame; a sphere's per pixel), a point light (hard textured shadows,
/// [Hasselgren 2007]) and per-pixel sample patterns through the same volumes and projection.
TEST(Stsv, DcsMasksEqualRaytraceForRoundAndPointLightsAndPerPixelPatterns) {
  for (LightShape shape : {LightShape::disk, LightShape::sphere, LightShape::point}) {
    Scene s = make_builtin_scene("fence");
    Light& l = s.lights[0];
    l.shape = shape;
    l.radius = 0.3f;
    l.normal = Vec3(0, -1, 0);
    const auto t =
        make_test_frame(std::move(s), 40, 40, grid_samples(shape == LightShape::point ? 1 : 8));
    expect_equal_masks(compare_masks(t, "dcs"), shape == LightShape::point ? 50 : 1000);
    const Diff w = diff(t, t.run("wedges"), t.run("raytrace"));
    EXPECT_LE(w.max_abs, 1e-6) << static_cast<int>(shape);
  }
  for (SamplePattern p : {SamplePattern::decorrelated, SamplePattern::poisson}) {
    LightSampleSpec spec;
    spec.pattern = p;
    spec.k = 8;
    spec.seed = 3;
    const auto t = make_test_frame("fence", 32, 32, spec);
    expect_equal_masks(compare_masks(t, "dcs"), 1000);
    EXPECT_LE(diff(t, t.run("wedges"), t.run("raytrace")).max_abs, 1e-6);
  }
}

/// A textured light: the STSV bitmask's occluded fraction per channel (emission-weighted) is
/// subtracted from each channel of the wedges' RGB visibility; on `fence` that is raytrace's RGB.
TEST(Stsv, TexturedLightRgbEqualsRaytrace) {
  const auto t = make_test_frame(test::with_textured_light(make_builtin_scene("fence")), 40, 40,
                                 grid_samples(8));
  const MethodResult rt = t.run("raytrace");
  for (const char* method : {"dcs", "wedges", "wedge_blend"}) {
    const MethodResult r = t.run(method);
    const Image<Vec3>& a = *r.per_light[0].lit_rgb;
    const Image<Vec3>& b = *rt.per_light[0].lit_rgb;
    double max_rgb = 0.0;
    int shadowed = 0;
    for (size_t i = 0; i < a.size(); ++i) {
      if (t.frame->receivers(0)[i] != kActive) continue;
      shadowed += b[i].x < 0.999f;
      for (int c = 0; c < 3; ++c) max_rgb = std::max(max_rgb, std::abs(double(a[i][c]) - b[i][c]));
    }
    std::printf("  %s vs raytrace: max |dRGB| %.2e over %d shadowed pixels\n", method, max_rgb,
                shadowed);
    EXPECT_LE(max_rgb, 1e-5) << method;
    EXPECT_LE(diff(t, r, rt).max_abs, 1e-5) << method;
    EXPECT_GT(shadowed, 300);
  }
}

// ---------------------------------------------------------------------------------------------
// wedges: the STSV bitmask V_coef added to the wedges' [§5.2.1].

TEST(Stsv, WedgesOnFenceTenTimesCloserToExactThanSolid) {
  const auto t = make_test_frame("fence", 64, 64, grid_samples(16));
  const MethodResult exact = t.run("exact");
  for (const char* method : {"wedges", "wedge_blend"}) {
    const Diff stsv = diff(t, t.run(method), exact);
    const Diff solid = diff(t, t.run(method, {{"alpha", "opaque"}}), exact);
    std::printf("  %s: mean |dV| over shadowed pixels stsv %.5f, opaque %.5f (ratio %.1f)\n",
                method, stsv.mean_abs_shadowed, solid.mean_abs_shadowed,
                solid.mean_abs_shadowed / stsv.mean_abs_shadowed);
    EXPECT_GE(solid.mean_abs_shadowed, 10.0 * stsv.mean_abs_shadowed) << method;
    // Measured (both methods: only S-triangles and the ground): 0.01077 (the 256 samples' error,
    // raytrace's), 0.3611 (the solid fence): 33.5 times.
    expect_measured(stsv.mean_abs_shadowed, 0.01077, 0.02, "stsv mean |dV| (shadowed)");
    expect_measured(solid.mean_abs_shadowed, 0.3611, 0.02, "opaque mean |dV| (shadowed)");
  }
  // Only S-triangles occlude here: the bitmask on the frame's samples is raytrace's answer.
  const Diff vs_rt = diff(t, t.run("wedges"), t.run("raytrace"));
  std::printf("  wedges vs raytrace: max |dV| %.2e\n", vs_rt.max_abs);
  EXPECT_LE(vs_rt.max_abs, 1e-6);
}

/// Two perforated quads overlapping as seen from the light: the bitmask ORs their samples, so
/// there is no underestimation between S-triangles [§5.2.1] (a sum of per-triangle fractions
/// would count the samples both block twice).
TEST(Stsv, WedgesOverlappingSTrianglesAreExactPerSample) {
  Scene s = make_builtin_scene("fence");
  Mesh second = make_quad(Vec3(0.15f, 1.5f, 0.1f), Vec3(0, 0, 1.2f), Vec3(1.2f, 0, 0));
  second.material = s.meshes[1].material;
  for (Vec2& uv : second.uvs) uv = Vec2(uv.y, uv.x);  // slats across the first quad's
  s.meshes.push_back(second);
  const auto t = make_test_frame(std::move(s), 48, 48, grid_samples(8));
  const MethodResult rt = t.run("raytrace");
  for (const char* method : {"wedges", "wedge_blend"}) {
    const Diff d = diff(t, t.run(method), rt);
    std::printf("  %s vs raytrace: max |dV| %.2e over %d shadowed pixels\n", method, d.max_abs,
                d.shadowed);
    EXPECT_LE(d.max_abs, 1e-6) << method;
    EXPECT_GT(d.shadowed, 500);
  }
}

/// Fig. 5.4(a): a perforated quad over an opaque one. `wedges` adds the wedges' occluded fraction
/// of the opaque quad and the STSV bitmask's of the perforated one: V = clamp(V_solid + V_stsv −
/// 1), so the light both block is counted twice and the overlap of their shadows is too dark. `dcs`
/// counts per sample and has no such artifact.
TEST(Stsv, WedgeOverlapArtifactOfFigure54) {
  Scene s = make_builtin_scene("fence");
  Mesh solid = make_quad(Vec3(0.2f, 0.7f, 0.1f), Vec3(0, 0, 0.9f), Vec3(0.9f, 0, 0));
  const int grey = static_cast<int>(s.materials.size());
  s.materials.push_back(Material{"solid", Vec3(0.5f), -1, 0.0f});
  solid.material = grey;
  s.meshes.push_back(solid);
  s.lights[0].edge_u *= 2.0f, s.lights[0].edge_v *= 2.0f;  // wide penumbrae: a large overlap
  // The same frame with one occluder each (neither casts: same G-buffer, same samples).
  Scene only_solid = s, only_fence = s;
  only_solid.meshes[1].casts_shadows = false;
  only_fence.meshes[2].casts_shadows = false;
  const int size = 64;
  const auto t = make_test_frame(std::move(s), size, size, grid_samples(16));
  const auto ts = make_test_frame(std::move(only_solid), size, size, grid_samples(16));
  const auto tf = make_test_frame(std::move(only_fence), size, size, grid_samples(16));
  const MethodResult exact = t.run("exact"), dcs = t.run("dcs"), wedges = t.run("wedges");
  const MethodResult solid_wedges = ts.run("wedges"), solid_exact = ts.run("exact");
  const MethodResult fence_rt = tf.run("raytrace");
  double dark_wedges = 0.0, dark_dcs = 0.0, max_dark = 0.0, max_formula = 0.0;
  int overlap = 0;
  for (size_t i = 0; i < exact.per_light[0].lit.size(); ++i) {
    if (t.frame->receivers(0)[i] != kActive) continue;
    const float vs = solid_wedges.per_light[0].lit[i], vf = fence_rt.per_light[0].lit[i];
    const float w = wedges.per_light[0].lit[i], e = exact.per_light[0].lit[i];
    // §5.2.1's sum of the two V_coefs, from the separate runs.
    max_formula = std::max(
        max_formula, static_cast<double>(std::abs(w - std::clamp(vs + vf - 1.0f, 0.0f, 1.0f))));
    if (!(solid_exact.per_light[0].lit[i] < 0.999f && vf < 0.999f && e > 1e-3f)) continue;
    ++overlap;  // both cast a shadow here, not the common umbra
    dark_wedges += e - w;
    dark_dcs += e - dcs.per_light[0].lit[i];
    max_dark = std::max(max_dark, static_cast<double>(e - w));
  }
  dark_wedges /= std::max(1, overlap), dark_dcs /= std::max(1, overlap);
  std::printf(
      "  overlap pixels %d: mean darkening wedges %.5f dcs %.5f, max wedges %.4f; "
      "|wedges - clamp(V_solid + V_stsv - 1)| max %.2e\n",
      overlap, dark_wedges, dark_dcs, max_dark, max_formula);
  EXPECT_LE(max_formula, 2e-6);
  EXPECT_GT(overlap, 250);  // measured 271
  // Measured: 0.1325 mean, 0.3239 max over the overlap; dcs 0.0016 (the samples' error alone).
  expect_measured(dark_wedges, 0.1325, 0.03, "wedges mean darkening (overlap)");
  expect_measured(max_dark, 0.3239, 0.03, "wedges max darkening (overlap)");
  EXPECT_LE(std::abs(dark_dcs), 0.005);
  EXPECT_GE(dark_wedges, 20.0 * std::abs(dark_dcs));
  const Diff dw = diff(t, wedges, exact), dd = diff(t, dcs, exact);
  std::printf("  mean |dV| (shadowed): wedges %.5f dcs %.5f\n", dw.mean_abs_shadowed,
              dd.mean_abs_shadowed);
}

// ---------------------------------------------------------------------------------------------
// Fully transparent and fully opaque textures.

TEST(Stsv, TransparentTextureCastsNothing) {
  Scene none = fence_with([](int, int) { return 0.0f; });
  Scene without = none;
  without.meshes[1].casts_shadows = false;
  const auto t = make_test_frame(none, 32, 32, grid_samples(8));
  const auto u = make_test_frame(without, 32, 32, grid_samples(8));
  for (const char* method : {"dcs", "wedges", "wedge_blend"}) {
    const MethodResult r = t.run(method);
    EXPECT_TRUE(same_lit(r, u.run(method))) << method;
    EXPECT_EQ(counter(r, "stsv_alpha_hole_triangles"), 2.0) << method;
  }
  // An S-triangle (its uv box holds an opaque texel) whose every lookup lands on a hole: the
  // texel (0, 63) lies in the box of triangle (0, 1, 2) but outside the triangle (u ≥ v there).
  Scene corner = fence_with([](int x, int y) { return x == 0 && y == 63 ? 1.0f : 0.0f; });
  corner.meshes[1].triangles.resize(1);
  const auto c = make_test_frame(corner, 32, 32, grid_samples(8));
  corner.meshes[1].casts_shadows = false;
  const auto c0 = make_test_frame(corner, 32, 32, grid_samples(8));
  for (const char* method : {"dcs", "wedges"}) {
    const MethodResult r = c.run(method);
    EXPECT_EQ(counter(r, "stsv_triangles"), 1.0) << method;
    EXPECT_GT(counter(r, "stsv_sample_lookups"), 1000.0) << method;
    EXPECT_EQ(counter(r, "stsv_blocked_samples"), 0.0) << method;
    EXPECT_TRUE(same_lit(r, c0.run(method))) << method;
  }
}

TEST(Stsv, OpaqueTextureEqualsTheOpaquePathBitForBit) {
  const auto t =
      make_test_frame(fence_with([](int, int) { return 1.0f; }), 32, 32, grid_samples(8));
  for (const char* method : {"dcs", "wedges", "wedge_blend"}) {
    const MethodResult stsv = t.run(method, {}, true), solid = t.run(method, {{"alpha", "opaque"}});
    EXPECT_TRUE(same_lit(stsv, solid)) << method;
    EXPECT_EQ(counter(stsv, "stsv_triangles"), 0.0) << method;
    EXPECT_EQ(counter(stsv, "stsv_alpha_opaque_triangles"), 2.0) << method;
  }
  expect_equal_masks(compare_masks(t, "dcs"), 1000);
}

// ---------------------------------------------------------------------------------------------
// Both sides cast [§5.5]; semi-opaque textured occluders.

/// A vertical perforated quad whose plane cuts the light: each half of the light is blocked from
/// the receivers on the other side. Its mirror image (reversed winding) casts the same.
TEST(Stsv, BothSidesOfATriangleCast) {
  for (const bool flip : {false, true}) {
    Scene s = make_builtin_scene("fence");
    s.meshes[1] = make_quad(Vec3(0.03f, 1.8f, 0.0f), Vec3(0, 1.4f, 0), Vec3(0, 0, 1.4f));
    s.meshes[1].material = s.materials.size() - 1;
    s.meshes[1].name = "wall";
    if (flip)
      for (Triangle& tri : s.meshes[1].triangles) std::swap(tri.v[1], tri.v[2]);
    s.camera.position = Vec3(0.0f, 3.5f, 2.5f);
    const auto t = make_test_frame(std::move(s), 48, 48, grid_samples(8));
    const MethodResult r = t.run("dcs");
    EXPECT_EQ(counter(r, "stsv_two_sided_volumes"), 2.0);
    expect_equal_masks(compare_masks(t, "dcs"), 1000);
    const Diff d = diff(t, t.run("wedges"), t.run("raytrace"));
    EXPECT_LE(d.max_abs, 1e-6);
  }
}

/// The fence material with transmittance 0.5 in `default`: each opaque texel the segment crosses
/// halves the sample (dcs: its own layer class [§4.3.3]; wedges: the LS_buffer sample).
TEST(Stsv, SemiOpaqueTexturedOccluderMatchesRaytrace) {
  Scene s = make_builtin_scene("default");
  for (Material& m : s.materials)
    if (m.alpha_texture >= 0) m.transmittance = 0.5f;
  const auto t = make_test_frame(std::move(s), 48, 48, grid_samples(8));
  const MethodResult rt = t.run("raytrace", {}, true);
  const MethodResult dcs = t.run("dcs", {}, true);
  const Diff d = diff(t, dcs, rt);
  std::printf("  dcs vs raytrace: max |dV| %.2e, layer classes %g\n", d.max_abs,
              counter(dcs, "layer_classes"));
  EXPECT_LE(d.max_abs, 2.0 / 64);  // at most two tie samples of 64 in a pixel
  EXPECT_LE(std::abs(d.mean_signed), 1e-4);
  EXPECT_EQ(counter(dcs, "layer_classes"), 2.0);
  expect_equal_masks(compare_masks(t, rt, dcs), 500);
  // Only the fence: the wedge methods' LS_buffer holds raytrace's transmittance per sample.
  Scene f = make_builtin_scene("fence");
  f.materials[f.meshes[1].material].transmittance = 0.5f;
  const auto tf = make_test_frame(std::move(f), 48, 48, grid_samples(8));
  const Diff w = diff(tf, tf.run("wedges"), tf.run("raytrace"));
  EXPECT_LE(w.max_abs, 1e-6);
  EXPECT_GT(w.shadowed, 300);
}

/// The benchmark's baseline (bench/bench_stsv.cpp): the fence's texel runs meshed as opaque quads
/// cast the shadow the alpha texture does, so the STSV-vs-mesh timing compares like with like.
TEST(Stsv, MeshedAlphaRunsCastTheSameShadow) {
  const Scene alpha = make_builtin_scene("fence");
  const Scene meshed = with_meshed_alpha(alpha);
  EXPECT_EQ(meshed.meshes[1].triangle_count(), 856u);  // 52 rows of 8 slats, 12 rail rows of 1
  const auto ta = make_test_frame(alpha, 48, 48, grid_samples(8));
  const auto tm = make_test_frame(meshed, 48, 48, grid_samples(8));
  const MethodResult dcs = ta.run("dcs", {}, true), rt_meshed = tm.run("raytrace", {}, true);
  const GBuffer& ga = ta.frame->gbuffer();
  const GBuffer& gm = tm.frame->gbuffer();
  const SampleMasks& ma = *dcs.per_light[0].masks;
  const SampleMasks& mm = *rt_meshed.per_light[0].masks;
  const int n = ta.frame->samples().count();
  std::vector<Vec2> uv(n);
  int same = 0;
  uint64_t pairs = 0, differ = 0, unexplained = 0;
  for (size_t i = 0; i < ga.pixel_count(); ++i) {
    if (ta.frame->receivers(0)[i] != kActive) continue;
    const Vec3 o = ga.shadow_origin(i);
    if (o != gm.shadow_origin(i)) continue;  // the fence itself, hit elsewhere
    ++same;
    ta.frame->samples().pixel_samples(static_cast<int>(i % ga.width),
                                      static_cast<int>(i / ga.width), uv);
    for (int s = 0; s < n; ++s) {
      ++pairs;
      if (ma.blocked(i, s) == mm.blocked(i, s)) continue;
      ++differ;  // a tie when the segment passes along a meshed quad's edge (a texel border)
      const Vec3 x = light_frame(ta.scene->lights[0], o).point(uv[s]);
      unexplained += !test::ambiguous(*tm.scene, DVec3(o), DVec3(x));
    }
  }
  std::printf(
      "  %d pixels with the same shadow origin: %llu of %llu samples differ, %llu not ties\n", same,
      static_cast<unsigned long long>(differ), static_cast<unsigned long long>(pairs),
      static_cast<unsigned long long>(unexplained));
  EXPECT_GT(same, 1500);
  EXPECT_LE(differ, pairs / 500);
  EXPECT_EQ(unexplained, 0u);
  expect_equal_masks(compare_masks(tm, "dcs"), 1000);  // and dcs on the meshed fence is exact
}

}  // namespace
}  // namespace penumbra
