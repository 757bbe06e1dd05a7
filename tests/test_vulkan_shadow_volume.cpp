// `shadow_volume` on Vulkan against the CPU method on the same frame: hard shadows from the light
// centre by z-fail counting, the volume faces drawn by the graphics pipeline and summed by
// additive blending, or walked in compute and summed by atomics. Both run the same double-precision
// per-pixel tests at the same shadow origins, so the counts — not only lit/shadowed — must be equal
// on every pixel.
#include <gtest/gtest.h>

#include <cstdlib>

#ifdef PENUMBRA_HAVE_VULKAN

#include <cstdio>

#include "penumbra/core/error.hpp"
#include "penumbra/render/receivers.hpp"
#include "penumbra/shadows/wedges/shadow_volume.hpp"
#include "support/vulkan_helpers.hpp"

namespace penumbra {
namespace {

using test::make_test_frame;

struct Agreement {
  size_t active = 0, differ = 0, shadowed = 0;
};

Agreement compare(gpu::Backend& backend, const test::TestFrame& t, const char* name) {
  Agreement a;
  if (!backend.context().has_float64()) {
    // The per-pixel tests are the CPU's, in double: refused with a clear error without it.
    EXPECT_THROW(test::run_vulkan(backend, t, "shadow_volume"), Error);
    return a;
  }
  const MethodResult gpu = test::run_vulkan(backend, t, "shadow_volume");
  const MethodResult cpu = t.run("shadow_volume", {});
  const Scene& scene = *t.scene;
  const Image<int32_t> counts =
      shadow_volume_counts(scene, scene.camera, t.frame->gbuffer(), t.frame->receivers(0),
                           hard_shadow_point(scene.lights[0]));
  double count_sum = 0.0, count_max = 0.0;
  for (size_t i = 0; i < t.frame->gbuffer().pixel_count(); ++i) {
    if (t.frame->receivers(0)[i] != kActive) continue;
    ++a.active;
    a.differ += cpu.per_light[0].lit[i] != gpu.per_light[0].lit[i];
    a.shadowed += cpu.per_light[0].lit[i] < 1.0f;
    count_sum += counts[i];
    count_max = std::max<double>(count_max, counts[i]);
  }
  const auto& c = gpu.per_light[0].counters;
  std::printf(
      "%s: %zu active, %zu shadowed, %zu differ; count sum %.0f (cpu %.0f), max %.0f, "
      "%.0f faces, %.0f silhouette edges\n",
      name, a.active, a.shadowed, a.differ, c.at("count_sum"), count_sum, c.at("count_max"),
      c.at("volume_faces"), c.at("silhouette_edges"));
  EXPECT_GT(a.shadowed, a.active / 50) << "the comparison needs shadows";
  // Measured: 0 pixels differ and equal count sums on every frame below.
  EXPECT_EQ(a.differ, 0u);
  EXPECT_EQ(c.at("count_sum"), count_sum);
  EXPECT_EQ(c.at("count_max"), count_max);
  EXPECT_EQ(c.at("negative_count_pixels"), 0.0);
  EXPECT_EQ(c.at("silhouette_edges"), cpu.per_light[0].counters.at("silhouette_edges"));
  EXPECT_EQ(backend.context().validation_messages(), 0u);
  return a;
}

TEST(VulkanShadowVolume, CountsEqualCpu) {
  PENUMBRA_VULKAN_BACKEND_OR_SKIP(backend);
  // fence: its alpha is ignored, as on the CPU (hard shadows of the whole quads).
  for (const char* scene : {"quad", "spheres", "fence"})
    compare(backend, make_test_frame(scene, 96, 96, LightSampleSpec{}), scene);
}

TEST(VulkanShadowVolume, DiskAndSphereLightCentres) {
  PENUMBRA_VULKAN_BACKEND_OR_SKIP(backend);
  compare(backend, make_test_frame(test::round_light_scene(LightShape::disk), 64, 64, {}),
          "disk light");
  compare(backend, make_test_frame(test::round_light_scene(LightShape::sphere), 64, 64, {}),
          "sphere light");
}

/// The camera inside the occluder's shadow volume, under the quad: its side quads and caps cross
/// the near plane (clipped as on the CPU) and z-fail needs no count at the eye.
TEST(VulkanShadowVolume, CameraInsideTheVolume) {
  PENUMBRA_VULKAN_BACKEND_OR_SKIP(backend);
  Scene scene = make_builtin_scene("quad");
  scene.camera.position = Vec3(0.05f, 0.3f, 0.1f);
  scene.camera.target = Vec3(1.2f, 0.0f, 1.5f);
  compare(backend, make_test_frame(std::move(scene), 64, 64, LightSampleSpec{}), "camera inside");
}

/// The count in compute alone (RasterPath::compute, the path of devices with few graphics units):
/// the same counts, camera inside the volume included (measured: 0 pixels differ).
TEST(VulkanShadowVolume, ComputeCountEqualsCpu) {
  PENUMBRA_VULKAN_BACKEND_OR_SKIP(shared);
  if (!shared.context().has_float64()) GTEST_SKIP() << "the per-pixel tests need shaderFloat64";
  setenv("PENUMBRA_VK_RASTER", "compute", 1);
  gpu::ContextOptions options;
  options.validation = true;
  gpu::Backend backend(options);
  unsetenv("PENUMBRA_VK_RASTER");
  ASSERT_EQ(backend.raster_path(), gpu::RasterPath::compute);
  for (const char* scene : {"quad", "spheres", "fence"})
    compare(backend, make_test_frame(scene, 96, 96, LightSampleSpec{}), scene);
  Scene inside = make_builtin_scene("quad");
  inside.camera.position = Vec3(0.05f, 0.3f, 0.1f);
  inside.camera.target = Vec3(1.2f, 0.0f, 1.5f);
  compare(backend, make_test_frame(std::move(inside), 64, 64, LightSampleSpec{}), "camera inside");
}

TEST(VulkanShadowVolume, ReportsGpuStageTimes) {
  PENUMBRA_VULKAN_BACKEND_OR_SKIP(backend);
  const test::TestFrame t = make_test_frame("spheres", 32, 32, LightSampleSpec{});
  if (!backend.context().has_float64()) return;  // CountsEqualCpu checks the error
  const MethodResult r = test::run_vulkan(backend, t, "shadow_volume");
  const StageTimes& times = r.per_light[0].times;
  for (const char* stage : {"gpu_setup", "gpu_count", "wall_gpu"})
    EXPECT_GT(times.get(stage), 0.0) << stage;
  EXPECT_GE(times.get("wall_gpu"), times.get("gpu_count"));
}

}  // namespace
}  // namespace penumbra

#else

TEST(VulkanShadowVolume, BuiltWithoutVulkan) {
  GTEST_SKIP() << "built without libvulkan-dev / glslc";
}

#endif
