// `ssm` (soft shadow maps, Atty 2006 §3): the micro-patch occlusion and FP16 rounding in isolation,
// then whole frames against `exact` with the paper's metric (mean |error| over the shadowed and
// penumbra pixels, Atty 2006 §4.2.1): the quad case, the occluder-map resolution sweep, one- vs
// two-pass, occluders touching the light or the receiver, and the FP16 blending of appendix A.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>

#include "penumbra/render/receivers.hpp"
#include "penumbra/scene/model_paths.hpp"
#include "penumbra/scene/shapes.hpp"
#include "penumbra/shadows/depth_maps/ssm.hpp"
#include "support/frame_helpers.hpp"

namespace penumbra {
namespace {

using test::make_test_frame;
using test::TestFrame;

LightSampleSpec few_samples() {
  LightSampleSpec s;
  s.pattern = SamplePattern::grid;
  s.k = 2;  // exact and ssm ignore the samples
  return s;
}

/// The paper's metric, ErrorStats::mean_abs_shadowed, over the active pixels of the receiver (the
/// ground, mesh 0, in every scene here): the paper measures the soft shadow map, i.e. the
/// receivers [Atty 2006 §4.2.1]; occluders get no shadow from ssm (no self-shadowing, §3.1).
ErrorStats ssm_error(const TestFrame& t, const std::map<std::string, std::string>& options,
                     const MethodResult& exact) {
  const MethodResult r = t.run("ssm", options);
  const Image<uint8_t>& rc = t.frame->receivers(0);
  const GBuffer& g = t.frame->gbuffer();
  Image<float> mask(rc.width(), rc.height(), 0.0f);
  for (size_t i = 0; i < rc.size(); ++i)
    mask.pixels()[i] = rc.pixels()[i] == kActive && g.mesh_id[i] == 0 ? 1.0f : 0.0f;
  for (float v : r.per_light[0].lit.pixels())
    EXPECT_TRUE(std::isfinite(v) && v >= 0.0f && v <= 1.0f);
  return compare_images(exact.per_light[0].lit, r.per_light[0].lit, &mask);
}

/// The quad scene with its occluder replaced (same material).
Scene quad_with(Mesh occluder) {
  Scene s = make_builtin_scene("quad");
  occluder.name = "occluder";
  occluder.material = s.meshes[1].material;
  s.meshes[1] = std::move(occluder);
  validate_scene(s);
  return s;
}

/// The quad's occluder turned by `deg` about the vertical axis through its centre: still parallel
/// to the light, no longer aligned with the occluder map's texels.
Scene rotated_quad(double deg) {
  const double c = std::cos(deg * kPi / 180.0), s = std::sin(deg * kPi / 180.0);
  const float h = 0.5f * kQuadScene.occluder_side;
  return quad_with(
      make_quad(Vec3(0, kQuadScene.occluder_height, 0),
                Vec3(static_cast<float>(2 * h * s), 0, static_cast<float>(2 * h * c)),
                Vec3(static_cast<float>(2 * h * c), 0, static_cast<float>(-2 * h * s))));
}

TEST(SsmPatch, BackProjectionArea) {
  // Patch of side 0.1 at depth 1 on the axis, receiver on the axis at depth 2: s = 2, the
  // back-projection is 0.2 wide, the light 1 wide → 0.04 of the light.
  EXPECT_NEAR(ssm::patch_occlusion(0, 0, 0.05, 0.05, 1.0, 0, 0, 2.0, 1.0, 1.0), 0.04, 1e-12);
  // Receiver point far to the side: the back-projection misses the light.
  EXPECT_EQ(ssm::patch_occlusion(0, 0, 0.05, 0.05, 1.0, 5.0, 0, 2.0, 1.0, 1.0), 0.0);
  // Half off the light edge in x: patch back-projected to [0.4, 0.6] in light units → half kept.
  EXPECT_NEAR(ssm::patch_occlusion(0.25, 0, 0.05, 0.05, 1.0, 0, 0, 2.0, 1.0, 1.0), 0.02, 1e-12);
  // Behind or at the receiver: nothing.
  EXPECT_EQ(ssm::patch_occlusion(0, 0, 0.05, 0.05, 2.0, 0, 0, 2.0, 1.0, 1.0), 0.0);
  EXPECT_EQ(ssm::patch_occlusion(0, 0, 0.05, 0.05, 3.0, 0, 0, 2.0, 1.0, 1.0), 0.0);
  // Touching the receiver (§4.1.2): finite; full occlusion right under it, none beside it.
  const double z = 2.0 * (1.0 - 1e-15);
  EXPECT_EQ(ssm::patch_occlusion(0, 0, 0.05, 0.05, z, 0.01, 0, 2.0, 1.0, 1.0), 1.0);
  EXPECT_EQ(ssm::patch_occlusion(0, 0, 0.05, 0.05, z, 0.2, 0, 2.0, 1.0, 1.0), 0.0);
  // Touching the light: a tiny patch still blocks its own (tiny) share.
  const double o = ssm::patch_occlusion(0, 0, 1e-9, 1e-9, 1e-8, 0, 0, 2.0, 1.0, 1.0);
  EXPECT_TRUE(std::isfinite(o));
  EXPECT_GE(o, 0.0);
}

TEST(SsmPatch, HalfRoundingMatchesAppendixA) {
  // [Atty 2006 App. A]: X + ε = X in FP16 if ε < 2^-10·X; 2048 + 1 = 2048, 0.5 + 1/2049 = 0.5.
  // The rule is truncation (round toward zero), the blend rounding fp16 mode uses.
  EXPECT_EQ(ssm::round_to_half(2048.0f + 1.0f, true), 2048.0f);
  EXPECT_EQ(ssm::round_to_half(0.5f + ssm::round_to_half(1.0f / 2049.0f), true), 0.5f);
  EXPECT_EQ(ssm::round_to_half(2048.0f + 1.0f), 2048.0f);                       // a tie: to even
  EXPECT_EQ(ssm::round_to_half(0.5f + 1.0f / 2049.0f), 0.5f + 1.0f / 2048.0f);  // to nearest
  EXPECT_EQ(ssm::round_to_half(1.0f + 1.0f / 1024.0f), 1.0f + 1.0f / 1024.0f);
  EXPECT_EQ(ssm::round_to_half(65504.0f), 65504.0f);
  EXPECT_TRUE(std::isinf(ssm::round_to_half(1e6f)));
  EXPECT_EQ(ssm::round_to_half(std::ldexp(1.0f, -24)), std::ldexp(1.0f, -24));  // subnormal
  EXPECT_EQ(ssm::round_to_half(std::ldexp(1.0f, -26)), 0.0f);
}

// The paper's own case [Atty 2006 §4.2.1]: a square parallel to the light. All micro-patches lie
// at one depth, so neighbouring back-projections neither overlap nor gap (eq. 1 with δh = 0) and
// the occluder map's window is fitted to the square (no staircase): what is left is the
// soft-shadow-map sampling — a 128² map over the penumbra read bilinearly — and float rounding.
// Measured 2.1e-4 (96², ssm_resolution 128); 0.002 is 3 % of the smallest penumbra step a 16-level
// display would show and 10× the measurement, so any error in the pyramid or the back-projection
// (a mis-scaled extent cuts the penumbra; a wrong scale shifts it by far more) fails it.
TEST(Ssm, QuadMatchesExact) {
  const TestFrame t = make_test_frame("quad", 96, 96, few_samples());
  const MethodResult exact = t.run("exact");
  {
    const ErrorStats all = compare_images(
        exact.per_light[0].lit, t.run("ssm", {{"ssm_resolution", "128"}}).per_light[0].lit);
    std::printf("    all pixels: mean abs (shadowed) %.5f, max %.4f over %zu shadowed px\n",
                all.mean_abs_shadowed, all.max_abs, all.shadowed_pixels);
  }
  for (const char* two : {"false", "true"}) {
    const ErrorStats e = ssm_error(t, {{"ssm_resolution", "128"}, {"two_pass", two}}, exact);
    std::printf("    two_pass=%s: mean abs (shadowed) %.5f, max %.4f over %zu shadowed px\n", two,
                e.mean_abs_shadowed, e.max_abs, e.shadowed_pixels);
    EXPECT_GT(e.shadowed_pixels, 500u);
    // Measured: mean 0.00010, max 0.074 — one umbra pixel whose point lands on a soft-shadow-map
    // texel the back-projected micro-patches under-cover (0.926 instead of 1; the micro-patch
    // gaps of [Atty 2006 §3.2]). Which texel a pixel reads moves with sub-texel shifts of the
    // shading point (the self-intersection offset), so the bound is on the gap, not on luck.
    EXPECT_LT(e.mean_abs_shadowed, 0.0003);
    EXPECT_LT(e.max_abs, 0.08);
  }
}

// [Atty 2006 §4.1.2, Fig. 17]: with the square turned 30° its edges cross the occluder-map texels,
// the staircase error is half a texel along the outline, and it falls as the resolution rises.
TEST(Ssm, ErrorFallsWithOccluderMapResolution) {
  const TestFrame t = make_test_frame(rotated_quad(30.0), 96, 96, few_samples());
  const MethodResult exact = t.run("exact");
  double previous = 1.0, first = 0.0, last = 0.0;
  for (int res : {32, 64, 128, 256}) {
    const double e =
        ssm_error(
            t,
            {{"resolution", std::to_string(res)}, {"ssm_resolution", "128"}, {"two_pass", "false"}},
            exact)
            .mean_abs_shadowed;
    std::printf("    resolution %3d: mean abs (shadowed) %.5f\n", res, e);
    EXPECT_LT(e, previous * 1.05) << "resolution " << res;
    if (res == 32) first = e;
    last = e;
    previous = e;
  }
  EXPECT_LT(last, 0.5 * first);
}

// [Atty 2006 §3.5, §4.2.3]: the two-pass version is never worse than the one-pass one (the square
// has no back faces: equal there).
void expect_two_pass_not_worse(const Scene& scene, const char* name) {
  const TestFrame t = make_test_frame(scene, 80, 80, few_samples());
  const MethodResult exact = t.run("exact");
  const double one =
      ssm_error(t, {{"two_pass", "false"}, {"ssm_resolution", "128"}}, exact).mean_abs_shadowed;
  const double two =
      ssm_error(t, {{"two_pass", "true"}, {"ssm_resolution", "128"}}, exact).mean_abs_shadowed;
  std::printf("    %s: one-pass %.5f, two-pass %.5f\n", name, one, two);
  EXPECT_LE(two, one * 1.001 + 1e-6) << name;
}

TEST(Ssm, TwoPassNeverWorseThanOnePass) {
  expect_two_pass_not_worse(make_builtin_scene("quad"), "quad");
  expect_two_pass_not_worse(quad_with(make_sphere(Vec3(0.1f, 1.2f, 0.05f), 0.4f, 16, 32)),
                            "floating sphere");
  expect_two_pass_not_worse(quad_with(make_box(Vec3(0.1f, 0.3f, 0.0f), Vec3(0.3f, 0.3f, 0.2f))),
                            "box on the ground");
  expect_two_pass_not_worse(make_builtin_scene("spheres"), "spheres");
}

TEST(Ssm, TwoPassNeverWorseOnBunny) {
  if (!find_model("bunny00.off")) GTEST_SKIP() << "bunny00.off not installed";
  expect_two_pass_not_worse(make_builtin_scene("bunny"), "bunny");
}

// [Atty 2006 §4.1.2]: an occluder touching the light or the receiver makes the overlap bound
// infinite; the method must still return finite visibilities in [0, 1] (Frame::run throws on a
// non-finite value) and a sane shadow.
TEST(Ssm, OccludersTouchingLightOrReceiverStayFinite) {
  const float top = kQuadScene.light_height;
  struct Case {
    const char* name;
    Mesh occluder;
  };
  const Case cases[] = {
      {"quad 1e-5 below the light",
       make_quad(Vec3(0, top - 1e-5f, 0), Vec3(0, 0, 0.6f), Vec3(0.6f, 0, 0))},
      {"quad 1e-5 above the ground", make_quad(Vec3(0, 1e-5f, 0), Vec3(0, 0, 1), Vec3(1, 0, 0))},
      {"box through the light plane", make_box(Vec3(0.2f, top, 0.1f), Vec3(0.2f, 0.3f, 0.2f))},
      {"box on the ground", make_box(Vec3(0, 0.25f, 0), Vec3(0.25f, 0.25f, 0.25f))},
  };
  for (const Case& c : cases) {
    const TestFrame t = make_test_frame(quad_with(c.occluder), 48, 48, few_samples());
    const MethodResult exact = t.run("exact");
    for (const char* two : {"false", "true"}) {
      for (const char* fp16 : {"false", "true"}) {
        const MethodResult r = t.run(
            "ssm",
            {{"two_pass", two}, {"fp16", fp16}, {"ssm_resolution", "64"}, {"resolution", "64"}});
        for (const auto& [key, value] : r.per_light[0].counters)
          EXPECT_TRUE(std::isfinite(value)) << c.name << ": counter " << key;
      }
    }
    // The error itself is unbounded here (§4.1.2: it grows as the occluder nears the light);
    // printed, not asserted. ssm_error checks every value is finite and in [0, 1].
    const ErrorStats e = ssm_error(t, {{"resolution", "64"}, {"ssm_resolution", "64"}}, exact);
    std::printf("    %s: mean abs (shadowed) %.4f\n", c.name, e.mean_abs_shadowed);
  }
}

// [Atty 2006 §4.1.3, App. A]: FP16 blending drops micro-patch contributions below 2^-10 of the
// running sum, so a high-resolution occluder map under-shadows; float32 accumulation does not.
TEST(Ssm, Fp16BlendingErrorGrowsWithResolution) {
  const TestFrame t = make_test_frame("quad", 64, 64, few_samples());
  const MethodResult exact = t.run("exact");
  const auto err = [&](int res, bool fp16) {
    return ssm_error(t,
                     {{"resolution", std::to_string(res)},
                      {"ssm_resolution", "64"},
                      {"two_pass", "false"},
                      {"fp16", fp16 ? "true" : "false"}},
                     exact)
        .mean_abs_shadowed;
  };
  const double f32 = err(256, false), h32 = err(32, true), h256 = err(256, true);
  std::printf("    fp32 @256 %.5f, fp16 @32 %.5f, fp16 @256 %.5f\n", f32, h32, h256);
  EXPECT_GT(h256, 2.0 * h32);
  EXPECT_GT(h256, 0.05);
  EXPECT_LT(f32, 0.01);
}

// The blending cost is occluder texels × extent texels [Atty 2006 §5.1]; a tall box whose top is
// close to the light gives every top texel an extent of most of the soft shadow map. One
// micro-patch per rectangle of equal-depth texels hides exactly what its texels hide (abutting
// back-projections telescope), so the answer changes only by float summation order.
TEST(Ssm, EqualDepthTexelsMergeIntoOnePatch) {
  const TestFrame t = make_test_frame(
      quad_with(make_box(Vec3(0, 1.25f, 0), Vec3(0.25f, 1.25f, 0.25f))), 32, 32, few_samples());
  const std::map<std::string, std::string> opts = {{"resolution", "64"}, {"ssm_resolution", "96"}};
  std::map<std::string, std::string> unmerged = opts;
  unmerged["merge"] = "false";
  const MethodResult a = t.run("ssm", opts), b = t.run("ssm", unmerged);
  const Visibility &va = a.per_light[0], &vb = b.per_light[0];
  double max_diff = 0.0;
  for (size_t i = 0; i < va.lit.size(); ++i)
    max_diff = std::max(max_diff, std::abs(static_cast<double>(va.lit[i]) - vb.lit[i]));
  const double ratio = vb.counters.at("update_bound") / va.counters.at("update_bound");
  std::printf("    max |dV| %.2e, patches %.0f vs %.0f, updates %.3g vs %.3g (%.0fx fewer)\n",
              max_diff, va.counters.at("patches"), vb.counters.at("patches"),
              va.counters.at("update_bound"), vb.counters.at("update_bound"), ratio);
  EXPECT_LT(max_diff, 2e-5);  // measured 1.1e-5
  EXPECT_GT(ratio, 80.0);     // measured 101x
  EXPECT_EQ(va.counters.at("budget_halvings"), 0.0);
}

// Above the update budget the occluder map is halved (§5.1: a large penumbra allows a lower
// resolution), never below 4², and the counters say so.
TEST(Ssm, BudgetHalvesTheOccluderMap) {
  const TestFrame t = make_test_frame(quad_with(make_sphere(Vec3(0, 2.4f, 0), 0.3f, 12, 24)), 32,
                                      32, few_samples());
  const MethodResult exact = t.run("exact");
  const std::map<std::string, std::string> full = {{"resolution", "64"}, {"ssm_resolution", "96"}};
  std::map<std::string, std::string> capped = full;
  capped["budget"] = "10";
  const MethodResult a = t.run("ssm", full), b = t.run("ssm", capped);
  const Visibility &va = a.per_light[0], &vb = b.per_light[0];
  const double ea = ssm_error(t, full, exact).mean_abs_shadowed;
  const double eb = ssm_error(t, capped, exact).mean_abs_shadowed;
  std::printf("    updates %.3g -> %.3g at %.0f² (%.0f halvings); error %.4f -> %.4f\n",
              va.counters.at("update_bound"), vb.counters.at("update_bound"),
              vb.counters.at("occluder_resolution"), vb.counters.at("budget_halvings"), ea, eb);
  EXPECT_EQ(va.counters.at("budget_halvings"), 0.0);
  EXPECT_GT(va.counters.at("update_bound"), 1e7);
  EXPECT_LE(vb.counters.at("update_bound"), 1e7);
  EXPECT_EQ(vb.counters.at("occluder_resolution"),
            64.0 / std::exp2(vb.counters.at("budget_halvings")));
  EXPECT_GE(vb.counters.at("budget_halvings"), 1.0);
  // A large penumbra needs no fine map: measured 0.1142 at 32² against 0.1138 at 64² (the
  // ASan build's rounding: 0.1148 against 0.1149).
  EXPECT_LT(eb, ea + 0.002);
  EXPECT_NEAR(ea, 0.1143, 0.002);
}

// Geometry far outside every receiver's reach must not spread the occluder map over empty space:
// a box 1e4 away leaves the quad's shadow as it is without it.
TEST(Ssm, FarOccludersDoNotCoarsenTheMap) {
  Scene far = make_builtin_scene("quad");
  Mesh box = make_box(Vec3(0, 1.0f, -1e4f), Vec3(0.25f, 0.25f, 0.25f));
  box.name = "far box";
  box.material = far.meshes[1].material;
  far.meshes.push_back(std::move(box));
  validate_scene(far);
  const std::map<std::string, std::string> opts = {{"resolution", "64"}, {"ssm_resolution", "96"}};
  const TestFrame t = make_test_frame(far, 48, 48, few_samples());
  const TestFrame t0 = make_test_frame("quad", 48, 48, few_samples());
  const double e = ssm_error(t, opts, t.run("exact")).mean_abs_shadowed;
  const double e0 = ssm_error(t0, opts, t0.run("exact")).mean_abs_shadowed;
  std::printf("    mean abs (shadowed): %.5f with the far box, %.5f without\n", e, e0);
  EXPECT_NEAR(e, e0, 1e-7);  // measured equal
}

TEST(Ssm, ReportsCountersAndStages) {
  const TestFrame t = make_test_frame("quad", 48, 48, few_samples());
  const MethodResult r = t.run("ssm", {{"resolution", "32"}, {"ssm_resolution", "64"}});
  const Visibility& v = r.per_light[0];
  EXPECT_EQ(v.counters.at("occluder_texels"), 32.0 * 32.0);  // the square fills its window
  EXPECT_GT(v.counters.at("penumbra_texels"), 0.0);
  for (const char* stage :
       {"fit", "occluder_map", "receiver_map", "patches", "ssm_front", "ssm_back", "project"})
    EXPECT_TRUE(std::any_of(v.times.stages().begin(), v.times.stages().end(), [&](const auto& s) {
      return s.first == stage;
    })) << stage;
}

}  // namespace
}  // namespace penumbra
