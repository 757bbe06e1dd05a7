// `wedges` and `wedge_blend` on Vulkan: the per-pixel pass on the GPU gives the CPU method's V —
// exactly (the same double sums in the same order; a round light's sector angle from a double
// atan2 written in GLSL, which agrees with std::atan2 on every pixel here) — with light splitting,
// the blend of several caster groups and the alpha fence's soft textured shadow volumes; a clear
// error for what stays on the CPU.
#include <gtest/gtest.h>

#ifdef PENUMBRA_HAVE_VULKAN

#include <cmath>
#include <cstdio>

#include "penumbra/core/error.hpp"
#include "penumbra/render/receivers.hpp"
#include "support/vulkan_helpers.hpp"

namespace penumbra {
namespace {

using test::grid_samples;
using test::make_test_frame;
using test::round_light_scene;

/// The GPU method against the CPU one: the largest and the mean |ΔV| over the active pixels.
void check_method(gpu::Backend& backend, const std::string& method, const test::TestFrame& t,
                  const std::string& name, double max_bound,
                  const std::map<std::string, std::string>& options = {}) {
  SCOPED_TRACE(method + " " + name);
  const MethodResult gpu = test::run_vulkan(backend, t, method, options);
  const MethodResult cpu = t.run(method, options);
  const Visibility &g = gpu.per_light[0], &c = cpu.per_light[0];
  const test::VisibilityDiff d = test::visibility_diff(t, cpu, gpu, 0.01f, 0.99f);  // penumbra
  std::printf("%s %s: %d active pixels, %d in penumbra, max |dV| %.3g, mean %.3g\n", method.c_str(),
              name.c_str(), d.active, d.between, d.max, d.mean);
  EXPECT_GT(d.between, 50);
  EXPECT_LE(d.max, max_bound);
  EXPECT_LE(d.mean, 1e-4);
  EXPECT_EQ(g.counters.at("wedges"), c.counters.at("wedges"));
  // The per-pixel pass's counters exist only where it ran on the CPU: left out, not reported as 0.
  EXPECT_GT(c.counters.at("pixel_tests"), 0.0);
  for (const char* counter :
       {"pixel_tests", "pixels_inside_wedges", "pixels_covered", "part_blends", "part_overlaps"})
    EXPECT_EQ(g.counters.count(counter), 0u) << counter;
  EXPECT_EQ(backend.context().validation_messages(), 0u);
}

void check_frame(gpu::Backend& backend, const test::TestFrame& t, const std::string& name,
                 double max_bound, const std::map<std::string, std::string>& options = {}) {
  check_method(backend, "wedges", t, name, max_bound, options);
}

TEST(VulkanWedges, EqualsCpuOnRectLight) {
  PENUMBRA_VULKAN_BACKEND_OR_SKIP(backend);
  check_frame(backend, make_test_frame("spheres", 48, 48, grid_samples(2)), "spheres", 0.0);
  check_frame(backend, make_test_frame("quad", 48, 48, grid_samples(2)), "quad", 0.0);
}

TEST(VulkanWedges, LightSplitting) {
  PENUMBRA_VULKAN_BACKEND_OR_SKIP(backend);
  check_frame(backend, make_test_frame("spheres", 40, 40, grid_samples(2)), "spheres split 2", 0.0,
              {{"split", "2"}});
}

TEST(VulkanWedges, FenceWithSoftTexturedShadowVolumes) {
  PENUMBRA_VULKAN_BACKEND_OR_SKIP(backend);
  check_frame(backend, make_test_frame("fence", 48, 48, grid_samples(2)), "fence", 0.0);
}

/// Round lights: the sector angle from the shaders' own double atan2 (GLSL has none).
TEST(VulkanWedges, DiskAndSphereLights) {
  PENUMBRA_VULKAN_BACKEND_OR_SKIP(backend);
  check_frame(backend,
              make_test_frame(round_light_scene(LightShape::disk), 40, 40, grid_samples(2)),
              "disk light", 0.0);
  check_frame(backend,
              make_test_frame(round_light_scene(LightShape::sphere), 40, 40, grid_samples(2)),
              "sphere light", 0.0);
}

/// The overlap approximation [Assarsson 2003 IV §5.1, eq. 1]: each caster group's clamped
/// coverage folded by max + ½ min, per pixel on the device, in the CPU's order.
TEST(VulkanWedges, OverlapApproximation) {
  PENUMBRA_VULKAN_BACKEND_OR_SKIP(backend);
  const std::map<std::string, std::string> overlap{{"overlap", "true"}};
  const auto spheres = make_test_frame("spheres", 48, 48, grid_samples(2));
  check_frame(backend, spheres, "spheres overlap", 0.0, overlap);
  // The approximation changes V where the spheres' penumbrae overlap: the test can tell.
  const test::VisibilityDiff d = test::visibility_diff(
      spheres, spheres.run("wedges"), test::run_vulkan(backend, spheres, "wedges", overlap));
  std::printf("spheres: overlap vs plain max |dV| %.3g\n", d.max);
  EXPECT_GT(d.max, 0.05);
  // The fence: its perforated triangles through soft textured shadow volumes (no wedges), and
  // solid (alpha=opaque), its wedges on the device.
  const auto fence = make_test_frame("fence", 40, 40, grid_samples(2));
  check_frame(backend, fence, "fence overlap", 0.0, overlap);
  check_frame(backend, fence, "opaque fence overlap", 0.0,
              {{"overlap", "true"}, {"alpha", "opaque"}});
  EXPECT_GT(test::run_vulkan(backend, fence, "wedges", {{"overlap", "true"}, {"alpha", "opaque"}})
                .per_light[0]
                .counters.at("wedges"),
            0.0);
  check_frame(backend,
              make_test_frame(round_light_scene(LightShape::disk), 40, 40, grid_samples(2)),
              "disk light overlap", 0.0, overlap);
  check_frame(backend,
              make_test_frame(round_light_scene(LightShape::sphere), 40, 40, grid_samples(2)),
              "sphere light overlap", 0.0, overlap);
}

/// A textured rectangle: each covered region weighed by the emission per channel
/// (coverage.cpp weighted_sector_minus_triangle), V and the RGB visible fractions as on the CPU;
/// with the split, each sub-light with its own part of the texture.
TEST(VulkanWedges, TexturedLight) {
  PENUMBRA_VULKAN_BACKEND_OR_SKIP(backend);
  const auto quad = make_test_frame(test::with_textured_light(make_builtin_scene("quad")), 32, 32,
                                    grid_samples(2));
  check_frame(backend, quad, "textured quad", 0.0);
  const MethodResult gpu = test::run_vulkan(backend, quad, "wedges");
  ASSERT_TRUE(gpu.per_light[0].lit_rgb.has_value());
  const auto spheres = make_test_frame(test::with_textured_light(make_builtin_scene("spheres")), 32,
                                       32, grid_samples(2));
  check_frame(backend, spheres, "textured spheres split 2 overlap", 0.0,
              {{"split", "2"}, {"overlap", "true"}});
  // marquee's 64 × 8 texture: regions clipped against many texels, one wedge per dispatch.
  check_frame(backend, make_test_frame("marquee", 32, 32, grid_samples(2)), "marquee", 0.0);
}

/// The coverage texture [Assarsson 2003 III §3.3] in place of the analytic area on a rectangle: the
/// CPU's table looked up on the device (nearest in a and bilinear in b, or quadrilinear); a
/// textured light's RGB table stays on the CPU (a clear error).
TEST(VulkanWedges, CoverageTexture) {
  PENUMBRA_VULKAN_BACKEND_OR_SKIP(backend);
  const auto spheres = make_test_frame("spheres", 40, 40, grid_samples(2));
  const std::map<std::string, std::string> table{{"coverage", "texture"}, {"texture_n", "16"}};
  check_frame(backend, spheres, "spheres coverage texture", 0.0, table);
  // The table's interpolation error: the test can tell a lookup from the analytic area.
  const test::VisibilityDiff d = test::visibility_diff(
      spheres, spheres.run("wedges"), test::run_vulkan(backend, spheres, "wedges", table));
  std::printf("spheres: coverage texture (n 16) vs analytic max |dV| %.3g\n", d.max);
  EXPECT_GT(d.max, 1e-4);
  check_frame(backend, spheres, "spheres quadrilinear overlap", 0.0,
              {{"coverage", "texture"},
               {"texture_n", "16"},
               {"lookup", "quadrilinear"},
               {"overlap", "true"}});
  const auto textured = make_test_frame(test::with_textured_light(make_builtin_scene("quad")), 16,
                                        16, grid_samples(2));
  EXPECT_THROW(test::run_vulkan(backend, textured, "wedges", {{"coverage", "texture"}}), Error);
}

/// wedge_blend: several caster groups per pixel (the spheres overlap as seen from the light), so
/// the SV-buffers are blended by eq. 3.1; exact on a rectangle, as on the CPU.
TEST(VulkanWedgeBlend, EqualsCpuOnRectLight) {
  PENUMBRA_VULKAN_BACKEND_OR_SKIP(backend);
  const auto spheres = make_test_frame("spheres", 48, 48, grid_samples(2));
  check_method(backend, "wedge_blend", spheres, "spheres", 0.0);
  const MethodResult gpu = test::run_vulkan(backend, spheres, "wedge_blend");
  EXPECT_GT(gpu.per_light[0].counters.at("groups"), 1.0);
  check_method(backend, "wedge_blend", make_test_frame("quad", 48, 48, grid_samples(2)), "quad",
               0.0);
}

TEST(VulkanWedgeBlend, FenceWithSoftTexturedShadowVolumes) {
  PENUMBRA_VULKAN_BACKEND_OR_SKIP(backend);
  const auto fence = make_test_frame("fence", 48, 48, grid_samples(2));
  check_method(backend, "wedge_blend", fence, "fence", 0.0);
  // Solid (alpha=opaque): the fence's wedges on the device.
  check_method(backend, "wedge_blend", fence, "opaque fence", 0.0, {{"alpha", "opaque"}});
}

TEST(VulkanWedgeBlend, DiskAndSphereLights) {
  PENUMBRA_VULKAN_BACKEND_OR_SKIP(backend);
  check_method(backend, "wedge_blend",
               make_test_frame(round_light_scene(LightShape::disk), 40, 40, grid_samples(2)),
               "disk light", 0.0);
  check_method(backend, "wedge_blend",
               make_test_frame(round_light_scene(LightShape::sphere), 40, 40, grid_samples(2)),
               "sphere light", 0.0);
}

/// A textured rectangle: every share (occlusion, rectangles, parts) in emitted power per channel
/// (wedge_blend.cpp LightMeasure), V and the RGB visible fractions as on the CPU.
TEST(VulkanWedgeBlend, TexturedLight) {
  PENUMBRA_VULKAN_BACKEND_OR_SKIP(backend);
  const auto quad = make_test_frame(test::with_textured_light(make_builtin_scene("quad")), 32, 32,
                                    grid_samples(2));
  check_method(backend, "wedge_blend", quad, "textured quad", 0.0);
  check_method(backend, "wedge_blend", make_test_frame("marquee", 32, 32, grid_samples(2)),
               "marquee", 0.0);
  // Overlapping groups: eq. 3.1's rectangles measured in emitted power (slow on lavapipe: 24²).
  const auto spheres = make_test_frame(test::with_textured_light(make_builtin_scene("spheres")), 24,
                                       24, grid_samples(2));
  const MethodResult cpu = spheres.run("wedge_blend");
  const MethodResult gpu = test::run_vulkan(backend, spheres, "wedge_blend");
  ASSERT_TRUE(cpu.per_light[0].lit_rgb.has_value());
  ASSERT_TRUE(gpu.per_light[0].lit_rgb.has_value());
  const test::VisibilityDiff d = test::visibility_diff(spheres, cpu, gpu, 0.01f, 0.99f);
  const double overlaps = cpu.per_light[0].counters.at("part_overlaps");
  std::printf(
      "wedge_blend textured spheres: %d active pixels, %d in penumbra, %.0f part overlaps, "
      "max |dV| (and RGB) %.3g\n",
      d.active, d.between, overlaps, d.max);
  EXPECT_GT(d.between, 50);
  EXPECT_GT(overlaps, 100.0);
  EXPECT_EQ(d.max, 0.0);
  EXPECT_EQ(backend.context().validation_messages(), 0u);
}

/// A frame of one 16×16 tile holds every wedge of the scene in one bin: 762 of the 27 spheres, and
/// about 100 000 of nest's 20 000 twigs, which one invocation cannot walk on lavapipe (65 535 loop
/// iterations: cut off, max |ΔV| 1 measured at 16²), walked in resumable steps over many
/// dispatches.
void check_big_bin(gpu::Backend& backend, const std::string& scene, int size, double min_wedges) {
  const auto t = make_test_frame(scene, size, size, grid_samples(2));
  const MethodResult cpu = t.run("wedge_blend");
  const MethodResult gpu = test::run_vulkan(backend, t, "wedge_blend");
  const test::VisibilityDiff d = test::visibility_diff(t, cpu, gpu);
  const double wedges = cpu.per_light[0].counters.at("wedges");
  std::printf("wedge_blend %s %dx%d: %.0f wedges in one bin, %d active pixels, max |dV| %.3g\n",
              scene.c_str(), size, size, wedges, d.active, d.max);
  EXPECT_GT(wedges, min_wedges);
  EXPECT_GT(d.active, 20);
  EXPECT_EQ(d.max, 0.0);
  EXPECT_EQ(backend.context().validation_messages(), 0u);
}

TEST(VulkanWedgeBlend, BigBinInChunks) {
  PENUMBRA_VULKAN_BACKEND_OR_SKIP(backend);
  check_big_bin(backend, "spheres", 16, 500.0);
  check_big_bin(backend, "nest", 8, 50000.0);
}

}  // namespace
}  // namespace penumbra

#else

TEST(VulkanWedges, BuiltWithoutVulkan) {
  GTEST_SKIP() << "built without libvulkan-dev / glslc";
}

#endif
