// `shadow_map` and `pcss` on Vulkan against the CPU methods on the same frame: the depth map from
// the graphics pipeline, the lookup in a compute shader. They may differ only where the two
// rasterizers disagree (float vs double vertex arithmetic at caster edges) or where a depth
// comparison is within float rounding (docs/gpu.md).
#include <gtest/gtest.h>

#ifdef PENUMBRA_HAVE_VULKAN

#include <cstdio>

#include "penumbra/gpu/depth_pass.hpp"
#include "penumbra/render/receivers.hpp"
#include "penumbra/shadows/wedges/shadow_volume.hpp"
#include "support/vulkan_helpers.hpp"

namespace penumbra {
namespace {

using test::make_test_frame;

struct Agreement {
  double differ_fraction = 0.0;  // of active pixels, |ΔV| > 1e-6
  double mean_abs = 0.0;
  double shadowed_fraction = 0.0;  // of active pixels, V < 1 on the CPU (the test has shadows)
};

Agreement compare(gpu::Backend& backend, const char* scene, const char* method,
                  const std::map<std::string, std::string>& options, int size = 96) {
  LightSampleSpec spec;
  spec.k = 4;
  const test::TestFrame t = make_test_frame(scene, size, size, spec);
  const MethodResult cpu = t.run(method, options);
  const MethodResult gpu = test::run_vulkan(backend, t, method, options);
  Agreement a;
  size_t active = 0, differ = 0, shadowed = 0;
  for (size_t i = 0; i < t.frame->gbuffer().pixel_count(); ++i) {
    if (t.frame->receivers(0)[i] != kActive) continue;
    ++active;
    const double d = std::abs(cpu.per_light[0].lit[i] - gpu.per_light[0].lit[i]);
    differ += d > 1e-6;
    a.mean_abs += d;
    shadowed += cpu.per_light[0].lit[i] < 1.0f;
  }
  a.differ_fraction = static_cast<double>(differ) / std::max<size_t>(active, 1);
  a.mean_abs /= std::max<size_t>(active, 1);
  a.shadowed_fraction = static_cast<double>(shadowed) / std::max<size_t>(active, 1);
  std::printf("%s %s: %zu active, %.2f%% shadowed, %zu differ (%.3f%%), mean |dV| %.2e\n", method,
              scene, active, 100.0 * a.shadowed_fraction, differ, 100.0 * a.differ_fraction,
              a.mean_abs);
  EXPECT_GT(a.shadowed_fraction, 0.02) << "the comparison needs shadows";
  EXPECT_LE(a.differ_fraction, 0.005);
  EXPECT_LE(a.mean_abs, 1e-3);
  EXPECT_EQ(backend.context().validation_messages(), 0u);
  return a;
}

TEST(VulkanDepthMaps, ShadowMapMatchesCpu) {
  PENUMBRA_VULKAN_BACKEND_OR_SKIP(backend);
  for (const char* scene : {"quad", "spheres", "fence"})
    compare(backend, scene, "shadow_map", {{"resolution", "512"}});
}

TEST(VulkanDepthMaps, ShadowMapPcfAndFaceSelectionMatchCpu) {
  PENUMBRA_VULKAN_BACKEND_OR_SKIP(backend);
  compare(backend, "spheres", "shadow_map", {{"resolution", "256"}, {"pcf", "3"}});
  // Closed casters: back faces only, and both — a wrong cull mode flips every caster pixel.
  compare(backend, "spheres", "shadow_map", {{"resolution", "512"}, {"faces", "back"}});
  compare(backend, "spheres", "shadow_map", {{"resolution", "512"}, {"faces", "both"}});
}

TEST(VulkanDepthMaps, PcssMatchesCpu) {
  PENUMBRA_VULKAN_BACKEND_OR_SKIP(backend);
  // The default map (2048²) and a coarser one. (At 512² on `quad` 0.6 % of the pixels differ, by
  // one PCF tap: four texels of 262144 change coverage at a caster edge and the wide blocker
  // search sees them; docs/gpu.md.)
  for (const char* scene : {"quad", "spheres"})
    for (const char* r : {"1024", "2048"}) compare(backend, scene, "pcss", {{"resolution", r}});
}

/// The maps themselves: equal to the float except where the two rasterizers' coverage differs at a
/// caster edge (Vulkan snaps vertices to its sub-texel grid, the CPU rasterizes in double).
TEST(VulkanDepthMaps, DepthMapEqualsCpuExceptAtEdges) {
  PENUMBRA_VULKAN_BACKEND_OR_SKIP(backend);
  gpu::VulkanContext& vk = backend.context();
  for (const char* name : {"quad", "spheres", "fence"}) {
    const test::TestFrame t = make_test_frame(name, 64, 64, LightSampleSpec{});
    std::vector<Vec3> cover;
    for (size_t i = 0; i < t.frame->gbuffer().pixel_count(); ++i)
      if (t.frame->receivers(0)[i] == kActive) cover.push_back(t.frame->gbuffer().shadow_origin(i));
    DepthMapSpec spec;
    spec.resolution = 512;
    const Vec3 eye = hard_shadow_point(t.scene->lights[0]);
    const DepthMap cpu = render_depth_map(*t.scene, eye, cover, spec);
    std::deque<gpu::Buffer> keep;
    std::deque<gpu::Image2D> images;
    gpu::CommandList cl(vk);
    const gpu::GpuDepthMap map = gpu::record_depth_map(vk, backend.depth_pipeline(), cl, *t.scene,
                                                       eye, cover, spec, keep, images);
    cl.submit();
    const std::vector<float> gpu_depth = vk.download<float>(map.depth, 512 * 512);
    size_t covered = 0, differ = 0;
    for (size_t i = 0; i < gpu_depth.size(); ++i) {
      const float c = cpu.depth.pixels()[i];
      const float g = gpu_depth[i] >= gpu::kEmptyDepth ? kInfinity : gpu_depth[i];
      covered += c < kInfinity;
      differ += c != g;
    }
    std::printf("%s: %zu covered texels, %zu differ\n", name, covered, differ);
    EXPECT_GT(covered, 5000u);
    // Measured: 2, 5 and 0 texels.
    EXPECT_LE(differ, 8u);
  }
}

TEST(VulkanDepthMaps, ReportsGpuStageTimes) {
  PENUMBRA_VULKAN_BACKEND_OR_SKIP(backend);
  const test::TestFrame t = make_test_frame("quad", 32, 32, LightSampleSpec{});
  const MethodResult r = test::run_vulkan(backend, t, "pcss", {{"resolution", "128"}});
  const StageTimes& times = r.per_light[0].times;
  for (const char* stage : {"gpu_depth_map", "gpu_min_depth", "gpu_filter", "wall_gpu"})
    EXPECT_GE(times.get(stage), 0.0) << stage;
  EXPECT_GT(times.get("wall_gpu"), 0.0);
  EXPECT_EQ(times.stages().size(), 6u);
}

}  // namespace
}  // namespace penumbra

#else

TEST(VulkanDepthMaps, BuiltWithoutVulkan) {
  GTEST_SKIP() << "built without libvulkan-dev / glslc";
}

#endif
