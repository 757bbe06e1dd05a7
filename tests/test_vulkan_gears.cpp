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

void expect_equal(const std::string& what, const test::MaskAgreement& a) {
  SCOPED_TRACE(what);
  std::printf("%s\n", what.c_str());
  test::expect_equal_masks(a, 1000);
}

/// GPU gears against CPU gears and against raytrace on one frame.
void check_frame(gpu::Backend& backend, const test::TestFrame& t, const std::string& name) {
  const MethodResult gpu = test::run_vulkan(backend, t, "gears", {}, true);
  const MethodResult cpu = t.run("gears", {}, true);
  const MethodResult rt = t.run("raytrace", {}, true);
  expect_equal(name + " vulkan vs cpu gears", test::compare_masks(t, cpu, gpu));
  expect_equal(name + " vulkan vs raytrace", test::compare_masks(t, rt, gpu));
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
  LightSampleSpec halton = grid_samples(4);
  halton.pattern = SamplePattern::halton;
  const test::TestFrame t = make_test_frame("quad", 16, 16, halton);
  EXPECT_THROW(test::run_vulkan(backend, t, "gears"), Error);
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
