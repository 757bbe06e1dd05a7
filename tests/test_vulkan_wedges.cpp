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

TEST(VulkanWedges, UnsupportedConfigurationsAreClearErrors) {
  PENUMBRA_VULKAN_BACKEND_OR_SKIP(backend);
  const auto t = make_test_frame("quad", 16, 16, grid_samples(2));
  EXPECT_THROW(test::run_vulkan(backend, t, "wedges", {{"overlap", "true"}}), Error);
  EXPECT_THROW(test::run_vulkan(backend, t, "wedges", {{"coverage", "texture"}}), Error);
  const auto textured = make_test_frame(test::with_textured_light(make_builtin_scene("quad")), 16,
                                        16, grid_samples(2));
  EXPECT_THROW(test::run_vulkan(backend, textured, "wedges"), Error);
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
  check_method(backend, "wedge_blend", make_test_frame("fence", 48, 48, grid_samples(2)), "fence",
               0.0);
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

TEST(VulkanWedgeBlend, TexturedLightIsAClearError) {
  PENUMBRA_VULKAN_BACKEND_OR_SKIP(backend);
  const auto textured = make_test_frame(test::with_textured_light(make_builtin_scene("quad")), 16,
                                        16, grid_samples(2));
  EXPECT_THROW(test::run_vulkan(backend, textured, "wedge_blend"), Error);
}

}  // namespace
}  // namespace penumbra

#else

TEST(VulkanWedges, BuiltWithoutVulkan) {
  GTEST_SKIP() << "built without libvulkan-dev / glslc";
}

#endif
