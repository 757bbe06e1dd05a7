// `gears` on Vulkan: the same per-sample masks as the CPU gears and as `raytrace` on the same
// light samples — quad, spheres, the alpha-textured fence, disk and sphere lights — every mismatch
// a tie on an occluder's edge within float rounding; the stage times from the GPU timestamps; a
// clear error for what the GPU path does not cover.
#include <gtest/gtest.h>

#ifdef PENUMBRA_HAVE_VULKAN

#include "penumbra/core/error.hpp"
#include "support/mask_agreement.hpp"
#include "support/vulkan_helpers.hpp"

namespace penumbra {
namespace {

using test::make_test_frame;
using test::round_light_scene;

using test::grid_samples;

void expect_equal(const std::string& what, const test::MaskAgreement& a, int min_blocked = 1000) {
  SCOPED_TRACE(what);
  std::printf("%s\n", what.c_str());
  test::expect_equal_masks(a, min_blocked);
}

/// GPU gears against CPU gears and against raytrace on one frame.
void check_frame(gpu::Backend& backend, const test::TestFrame& t, const std::string& name,
                 int min_blocked = 1000) {
  const MethodResult gpu = test::run_vulkan(backend, t, "gears", {}, true);
  const MethodResult cpu = t.run("gears", {}, true);
  const MethodResult rt = t.run("raytrace", {}, true);
  expect_equal(name + " vulkan vs cpu gears", test::compare_masks(t, cpu, gpu), min_blocked);
  expect_equal(name + " vulkan vs raytrace", test::compare_masks(t, rt, gpu), min_blocked);
  EXPECT_GT(gpu.per_light[0].counters.at("pairs"), 0.0);
  EXPECT_EQ(backend.context().validation_messages(), 0u);
}

TEST(VulkanGears, MasksEqualCpuAndRaytraceOnQuad) {
  PENUMBRA_VULKAN_BACKEND_OR_SKIP(backend);
  check_frame(backend, make_test_frame("quad", 64, 64, grid_samples(16)), "quad");
}

TEST(VulkanGears, MasksEqualCpuAndRaytraceOnSpheres) {
  PENUMBRA_VULKAN_BACKEND_OR_SKIP(backend);
  check_frame(backend, make_test_frame("spheres", 64, 64, grid_samples(16)), "spheres");
}

TEST(VulkanGears, MasksEqualCpuAndRaytraceOnFenceWithAlpha) {
  PENUMBRA_VULKAN_BACKEND_OR_SKIP(backend);
  check_frame(backend, make_test_frame("fence", 64, 64, grid_samples(16)), "fence");
}

TEST(VulkanGears, DiskLight) {
  PENUMBRA_VULKAN_BACKEND_OR_SKIP(backend);
  check_frame(backend,
              make_test_frame(round_light_scene(LightShape::disk), 48, 48, grid_samples(8)),
              "disk light");
}

/// Per-pixel light frames (the sphere's silhouette disk from each pixel).
TEST(VulkanGears, SphereLight) {
  PENUMBRA_VULKAN_BACKEND_OR_SKIP(backend);
  check_frame(backend,
              make_test_frame(round_light_scene(LightShape::sphere), 48, 48, grid_samples(8)),
              "sphere light");
}

/// The per-sample rasterizer: a point light (one sample at the light), irregular shared and
/// per-pixel patterns, and k > 32.
TEST(VulkanGears, PointLight) {
  PENUMBRA_VULKAN_BACKEND_OR_SKIP(backend);
  Scene scene = make_builtin_scene("spheres");
  scene.lights[0].shape = LightShape::point;
  check_frame(backend, make_test_frame(std::move(scene), 48, 48, grid_samples(2)), "point light",
              100);
}

TEST(VulkanGears, HaltonPattern) {
  PENUMBRA_VULKAN_BACKEND_OR_SKIP(backend);
  check_frame(backend,
              make_test_frame("spheres", 40, 40, test::sample_spec(SamplePattern::halton, 8, 5)),
              "halton");
}

TEST(VulkanGears, PerPixelPatternOnFenceWithAlpha) {
  PENUMBRA_VULKAN_BACKEND_OR_SKIP(backend);
  check_frame(
      backend,
      make_test_frame("fence", 40, 40, test::sample_spec(SamplePattern::decorrelated, 8, 5)),
      "fence decorrelated");
}

TEST(VulkanGears, SphereLightPerPixelPattern) {
  PENUMBRA_VULKAN_BACKEND_OR_SKIP(backend);
  check_frame(backend,
              make_test_frame(round_light_scene(LightShape::sphere), 32, 32,
                              test::sample_spec(SamplePattern::interleaved, 6, 5)),
              "sphere light interleaved");
}

TEST(VulkanGears, MoreThan32By32Samples) {
  PENUMBRA_VULKAN_BACKEND_OR_SKIP(backend);
  check_frame(backend, make_test_frame("spheres", 24, 24, grid_samples(40)), "k = 40");
}

TEST(VulkanGears, ReportsGpuStageTimes) {
  PENUMBRA_VULKAN_BACKEND_OR_SKIP(backend);
  const test::TestFrame t = make_test_frame("spheres", 32, 32, grid_samples(4));
  const MethodResult r = test::run_vulkan(backend, t, "gears");
  const StageTimes& times = r.per_light[0].times;
  for (const char* stage : {"gpu_pixel_cells", "gpu_triangle_count", "gpu_prefix_sum",
                            "gpu_pair_write", "gpu_radix_sort", "gpu_cell_ranges", "gpu_rasterize"})
    EXPECT_GT(times.get(stage), 0.0) << stage;
  EXPECT_GE(times.get("wall_gpu"), times.get("gpu_rasterize"));
}

TEST(VulkanGears, UnsupportedConfigurationsAreClearErrors) {
  PENUMBRA_VULKAN_BACKEND_OR_SKIP(backend);
  const test::TestFrame t2 = make_test_frame("quad", 16, 16, grid_samples(4));
  EXPECT_THROW(test::run_vulkan(backend, t2, "gears", {{"variant", "lut"}}), Error);
}

}  // namespace
}  // namespace penumbra

#else

TEST(VulkanGears, BuiltWithoutVulkan) {
  GTEST_SKIP() << "built without libvulkan-dev / glslc";
}

#endif
