// `ssm` on Vulkan: the micro-patches' blending into the soft shadow map on the GPU gives the CPU
// method's soft shadow maps, hence the same V on every pixel — rect, disk and sphere lights, the
// alpha fence (its bars opaque, as on the CPU), one- and two-pass; a clear error for fp16.
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

/// GPU ssm against the CPU ssm on one frame: V equal on every active pixel.
void check_frame(gpu::Backend& backend, const test::TestFrame& t, const std::string& name,
                 std::map<std::string, std::string> options = {}) {
  SCOPED_TRACE(name);
  options.emplace("resolution", "64");
  options.emplace("ssm_resolution", "128");
  const MethodResult gpu = test::run_vulkan(backend, t, "ssm", options);
  const MethodResult cpu = t.run("ssm", options);
  const Visibility &g = gpu.per_light[0], &c = cpu.per_light[0];
  const test::VisibilityDiff d = test::visibility_diff(t, cpu, gpu, -1.0f, 0.99f);  // shadowed
  std::printf("%s: %d active pixels, %d shadowed, max |dV| %.3g, mean %.3g, %g texel updates\n",
              name.c_str(), d.active, d.between, d.max, d.mean, g.counters.at("penumbra_texels"));
  EXPECT_GT(d.between, 100);
  EXPECT_EQ(d.max, 0.0);
  EXPECT_EQ(g.counters.at("penumbra_texels"), c.counters.at("penumbra_texels"));
  EXPECT_EQ(backend.context().validation_messages(), 0u);
}

TEST(VulkanSsm, EqualsCpuOnSpheres) {
  PENUMBRA_VULKAN_BACKEND_OR_SKIP(backend);
  const auto t = make_test_frame("spheres", 48, 48, grid_samples(4));
  check_frame(backend, t, "spheres two-pass");
  check_frame(backend, t, "spheres one-pass", {{"two_pass", "false"}});
}

TEST(VulkanSsm, EqualsCpuOnFence) {
  PENUMBRA_VULKAN_BACKEND_OR_SKIP(backend);
  check_frame(backend, make_test_frame("fence", 48, 48, grid_samples(4)), "fence");
}

TEST(VulkanSsm, EqualsCpuWithoutMerging) {
  PENUMBRA_VULKAN_BACKEND_OR_SKIP(backend);
  check_frame(backend, make_test_frame("quad", 48, 48, grid_samples(4)), "quad merge=false",
              {{"merge", "false"}});
}

TEST(VulkanSsm, DiskAndSphereLights) {
  PENUMBRA_VULKAN_BACKEND_OR_SKIP(backend);
  check_frame(backend,
              make_test_frame(round_light_scene(LightShape::disk), 40, 40, grid_samples(4)),
              "disk light");
  check_frame(backend,
              make_test_frame(round_light_scene(LightShape::sphere), 40, 40, grid_samples(4)),
              "sphere light");
}

TEST(VulkanSsm, Fp16IsAClearError) {
  PENUMBRA_VULKAN_BACKEND_OR_SKIP(backend);
  const auto t = make_test_frame("quad", 16, 16, grid_samples(2));
  EXPECT_THROW(test::run_vulkan(backend, t, "ssm", {{"fp16", "true"}}), Error);
}

}  // namespace
}  // namespace penumbra

#else

TEST(VulkanSsm, BuiltWithoutVulkan) {
  GTEST_SKIP() << "built without libvulkan-dev / glslc";
}

#endif
