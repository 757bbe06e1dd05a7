// `shadow_map` and `pcss` on Vulkan against the CPU methods on the same frame: the depth map from
// the graphics pipeline or from compute alone, the lookup in a compute shader. With shaderFloat64
// (lavapipe, NVIDIA) the depth pass applies the CPU rasterizer's coverage and depth in double, so
// maps and visibilities are equal; the hardware-coverage fallback differs only at caster-edge
// texels (docs/gpu.md).
#include <gtest/gtest.h>

#ifdef PENUMBRA_HAVE_VULKAN

#include <cstdio>
#include <cstdlib>

#include "penumbra/core/error.hpp"
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

// Measured on lavapipe with the exact depth pass: 0 pixels differ in every case below. The bounds
// leave room for a rounding tie or two (an FMA the host compiler contracts in the CPU rasterizer),
// ten times inside the backend's documented bound (0.5 % of pixels, mean |ΔV| 1e-3; docs/gpu.md).
constexpr double kMaxDifferFraction = 5e-4;
constexpr double kMaxMeanAbs = 1e-4;

Agreement compare(gpu::Backend& backend, const test::TestFrame& t, const char* scene,
                  const char* method, const std::map<std::string, std::string>& options) {
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
  EXPECT_LE(a.differ_fraction, kMaxDifferFraction);
  EXPECT_LE(a.mean_abs, kMaxMeanAbs);
  EXPECT_EQ(backend.context().validation_messages(), 0u);
  return a;
}

Agreement compare(gpu::Backend& backend, const char* scene, const char* method,
                  const std::map<std::string, std::string>& options, int size = 96) {
  LightSampleSpec spec;
  spec.k = 4;
  return compare(backend, make_test_frame(scene, size, size, spec), scene, method, options);
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
  // The default map (2048²) and coarser ones. (With hardware coverage, 512² on `quad` had 0.6 % of
  // the pixels differ by one PCF tap: four edge texels of 262144 changed coverage and the wide
  // blocker search saw them.)
  const std::pair<const char*, const char*> cases[] = {{"quad", "512"},
                                                       {"spheres", "512"},
                                                       {"spheres", "1024"},
                                                       {"spheres", "2048"},
                                                       {"fence", "512"}};
  for (const auto& [scene, r] : cases) compare(backend, scene, "pcss", {{"resolution", r}});
}

/// Round lights: the map from the light's centre; PCSS's blocker search and filter widths from the
/// disk's or sphere's radius (measured: 0 pixels differ for either method and shape).
TEST(VulkanDepthMaps, DiskAndSphereLightsMatchCpu) {
  PENUMBRA_VULKAN_BACKEND_OR_SKIP(backend);
  LightSampleSpec spec;
  spec.k = 4;
  for (const LightShape shape : {LightShape::disk, LightShape::sphere}) {
    const test::TestFrame t = make_test_frame(test::round_light_scene(shape), 64, 64, spec);
    const char* name = shape == LightShape::disk ? "disk light" : "sphere light";
    compare(backend, t, name, "shadow_map", {{"resolution", "512"}});
    compare(backend, t, name, "pcss", {{"resolution", "512"}});
  }
}

/// Texels of the 512² map of each built-in scene that differ from the CPU's render_depth_map, drawn
/// by `pipe`.
std::vector<size_t> depth_map_differences(gpu::VulkanContext& vk, gpu::DepthPipeline& pipe,
                                          FaceSelect faces = FaceSelect::front) {
  std::vector<size_t> out;
  for (const char* name : {"quad", "spheres", "fence"}) {
    const test::TestFrame t = make_test_frame(name, 64, 64, LightSampleSpec{});
    std::vector<Vec3> cover;
    for (size_t i = 0; i < t.frame->gbuffer().pixel_count(); ++i)
      if (t.frame->receivers(0)[i] == kActive) cover.push_back(t.frame->gbuffer().shadow_origin(i));
    DepthMapSpec spec;
    spec.resolution = 512;
    spec.faces = faces;
    const Vec3 eye = hard_shadow_point(t.scene->lights[0]);
    const DepthMap cpu = render_depth_map(*t.scene, eye, cover, spec);
    std::deque<gpu::Buffer> keep;
    std::deque<gpu::Image2D> images;
    gpu::CommandList cl(vk);
    const gpu::GpuDepthMap map =
        gpu::record_depth_map(vk, pipe, cl, *t.scene, eye, cover, spec, keep, images);
    cl.submit();
    const std::vector<float> gpu_depth = vk.download<float>(map.depth, 512 * 512);
    size_t covered = 0, differ = 0;
    for (size_t i = 0; i < gpu_depth.size(); ++i) {
      const float c = cpu.depth.pixels()[i];
      const float g = gpu_depth[i] >= gpu::kEmptyDepth ? kInfinity : gpu_depth[i];
      covered += c < kInfinity;
      // Exact pass: bit-equal. Hardware pass: its float interpolation of the view depth is within
      // 1e-5 relative, so count coverage changes and larger depth differences.
      differ +=
          pipe.exact() ? c != g : (c < kInfinity) != (g < kInfinity) || std::abs(c - g) > 1e-5f * c;
    }
    std::printf("%s (%s): %zu covered texels, %zu differ\n", name,
                pipe.exact() ? "exact" : "hardware", covered, differ);
    EXPECT_GT(covered, 5000u);
    out.push_back(differ);
  }
  EXPECT_EQ(vk.validation_messages(), 0u);
  return out;
}

/// The exact pass: the CPU's map texel for texel (measured: 0 differ on each scene and face set).
/// A device without shaderFloat64 draws the hardware pass, bounded below.
TEST(VulkanDepthMaps, DepthMapEqualsCpu) {
  PENUMBRA_VULKAN_BACKEND_OR_SKIP(backend);
  gpu::DepthPipeline& pipe = backend.depth_pipeline();
  EXPECT_EQ(pipe.exact(), backend.context().has_float64());
  for (FaceSelect faces : {FaceSelect::front, FaceSelect::both})
    for (size_t differ : depth_map_differences(backend.context(), pipe, faces))
      EXPECT_LE(differ, pipe.exact() ? 0u : 4u);
}

/// The exact pass rasterized in compute (the path of devices with few graphics units): the CPU's
/// map texel for texel too.
TEST(VulkanDepthMaps, ComputeRasterEqualsCpu) {
  PENUMBRA_VULKAN_BACKEND_OR_SKIP(backend);
  if (!backend.context().has_float64()) GTEST_SKIP() << "the exact pass needs shaderFloat64";
  gpu::DepthPipeline compute(backend.context(), true, gpu::RasterPath::compute);
  ASSERT_TRUE(compute.compute());
  for (FaceSelect faces : {FaceSelect::front, FaceSelect::both})
    for (size_t differ : depth_map_differences(backend.context(), compute, faces))
      EXPECT_EQ(differ, 0u);
}

TEST(VulkanDepthMaps, RasterPathFromTheEnvironment) {
  PENUMBRA_VULKAN_BACKEND_OR_SKIP(backend);
  setenv("PENUMBRA_VK_RASTER", "compute", 1);
  EXPECT_EQ(gpu::raster_path_for(backend.context()), gpu::RasterPath::compute);
  setenv("PENUMBRA_VK_RASTER", "graphics", 1);
  EXPECT_EQ(gpu::raster_path_for(backend.context()), gpu::RasterPath::graphics);
  setenv("PENUMBRA_VK_RASTER", "fast", 1);
  EXPECT_THROW(gpu::raster_path_for(backend.context()), Error);
  unsetenv("PENUMBRA_VK_RASTER");
  // lavapipe is not a data-centre GPU: the graphics pipeline by default.
  EXPECT_EQ(gpu::raster_path_for(backend.context()), gpu::RasterPath::graphics);
}

/// The fallback of devices without shaderFloat64: hardware coverage differs from the CPU only at
/// a few caster-edge texels (Vulkan snaps vertices to its sub-texel grid, 8 bits on lavapipe;
/// measured 0, 1 and 0 texels of 262144, depth within 1e-5 relative elsewhere).
TEST(VulkanDepthMaps, HardwareCoverageDiffersOnlyAtEdges) {
  PENUMBRA_VULKAN_BACKEND_OR_SKIP(backend);
  gpu::DepthPipeline hardware(backend.context(), false);
  size_t total = 0;
  for (size_t differ : depth_map_differences(backend.context(), hardware)) total += differ;
  EXPECT_LE(total, 4u);
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
