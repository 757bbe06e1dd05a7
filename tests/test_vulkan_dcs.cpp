// `dcs` on Vulkan: the same per-sample masks and the same visibility as the CPU dcs (hence as
// `raytrace`) — quad, spheres, the alpha fence (soft textured shadow volumes, and as opaque),
// rect, disk, sphere and point lights,
// an irregular shared pattern, per-pixel patterns, a textured light in RGB, semi-opaque occluders
// (exact product and the paper's approximation); a clear error for what the GPU path does not
// cover.
#include <gtest/gtest.h>

#ifdef PENUMBRA_HAVE_VULKAN

#include <cmath>
#include <cstdio>

#include "penumbra/core/error.hpp"
#include "penumbra/render/receivers.hpp"
#include "penumbra/scene/shapes.hpp"
#include "support/mask_agreement.hpp"
#include "support/vulkan_helpers.hpp"

namespace penumbra {
namespace {

using test::grid_samples;
using test::make_test_frame;
using test::round_light_scene;

/// GPU dcs against the CPU dcs (identical masks and V) and, where the CPU dcs is raytrace's
/// answer, against raytrace.
void check_frame(gpu::Backend& backend, const test::TestFrame& t, const std::string& name,
                 const std::map<std::string, std::string>& options = {}, bool vs_raytrace = true,
                 int min_blocked = 100) {
  SCOPED_TRACE(name);
  const MethodResult gpu = test::run_vulkan(backend, t, "dcs", options, true);
  const MethodResult cpu = t.run("dcs", options, true);
  const test::MaskAgreement vs_cpu = test::compare_masks(t, cpu, gpu, false);
  std::printf("%s: %llu pairs, %d blocked, %llu differ from the CPU dcs, max |dV| %.3g\n",
              name.c_str(), static_cast<unsigned long long>(vs_cpu.pairs), vs_cpu.blocked,
              static_cast<unsigned long long>(vs_cpu.differ),
              test::visibility_diff(t, cpu, gpu).max);
  EXPECT_GT(vs_cpu.blocked, min_blocked);
  EXPECT_EQ(vs_cpu.differ, 0u);
  EXPECT_EQ(test::visibility_diff(t, cpu, gpu).max, 0.0);
  if (vs_raytrace)
    test::expect_equal_masks(test::compare_masks(t, t.run("raytrace", {}, true), gpu));
  EXPECT_EQ(backend.context().validation_messages(), 0u);
}

TEST(VulkanDcs, EqualsCpuAndRaytraceOnQuad) {
  PENUMBRA_VULKAN_BACKEND_OR_SKIP(backend);
  check_frame(backend, make_test_frame("quad", 48, 48, grid_samples(8)), "quad");
}

TEST(VulkanDcs, EqualsCpuAndRaytraceOnSpheres) {
  PENUMBRA_VULKAN_BACKEND_OR_SKIP(backend);
  check_frame(backend, make_test_frame("spheres", 64, 48, grid_samples(8)), "spheres");
}

TEST(VulkanDcs, EqualsCpuWithLightCentreSilhouettes) {
  PENUMBRA_VULKAN_BACKEND_OR_SKIP(backend);
  check_frame(backend, make_test_frame("spheres", 40, 40, grid_samples(8)), "spheres centre",
              {{"silhouettes", "centre"}}, false);
}

TEST(VulkanDcs, DiskLight) {
  PENUMBRA_VULKAN_BACKEND_OR_SKIP(backend);
  check_frame(backend,
              make_test_frame(round_light_scene(LightShape::disk), 48, 48, grid_samples(8)),
              "disk light");
}

/// Per-pixel light frames (the sphere's silhouette disk from each pixel).
TEST(VulkanDcs, SphereLight) {
  PENUMBRA_VULKAN_BACKEND_OR_SKIP(backend);
  check_frame(backend,
              make_test_frame(round_light_scene(LightShape::sphere), 48, 48, grid_samples(8)),
              "sphere light");
}

/// The point-light limit: the centre counts alone.
TEST(VulkanDcs, PointLight) {
  PENUMBRA_VULKAN_BACKEND_OR_SKIP(backend);
  Scene scene = make_builtin_scene("spheres");
  scene.lights[0].shape = LightShape::point;
  check_frame(backend, make_test_frame(std::move(scene), 48, 48, grid_samples(2)), "point light");
}

/// An irregular pattern shared by every pixel (sorted into the same bands as on the CPU).
TEST(VulkanDcs, HaltonPattern) {
  PENUMBRA_VULKAN_BACKEND_OR_SKIP(backend);
  check_frame(backend,
              make_test_frame("spheres", 40, 40, test::sample_spec(SamplePattern::halton, 8, 5)),
              "halton");
}

/// The alpha fence through soft textured shadow volumes [Forest 2008 §5.2.2].
TEST(VulkanDcs, EqualsCpuAndRaytraceOnFenceWithAlpha) {
  PENUMBRA_VULKAN_BACKEND_OR_SKIP(backend);
  check_frame(backend, make_test_frame("fence", 48, 48, grid_samples(8)), "fence alpha=stsv");
}

/// The fence's alpha-textured bars as opaque triangles (alpha=opaque): the CPU dcs's answer.
TEST(VulkanDcs, FenceWithAlphaAsOpaque) {
  PENUMBRA_VULKAN_BACKEND_OR_SKIP(backend);
  check_frame(backend, make_test_frame("fence", 48, 48, grid_samples(8)), "fence alpha=opaque",
              {{"alpha", "opaque"}}, false);
}

/// Eq. 4.2: the per-sample emission weights (host) from the GPU's per-sample visibility.
TEST(VulkanDcs, TexturedLightRgb) {
  PENUMBRA_VULKAN_BACKEND_OR_SKIP(backend);
  check_frame(backend,
              make_test_frame(test::with_textured_light(make_builtin_scene("spheres")), 40, 40,
                              grid_samples(8)),
              "textured light");
}

/// The spheres made semi-opaque, and one opaque ball among them: two layer classes.
Scene semi_opaque(Scene scene, float transmittance) {
  Material glass;
  glass.name = "glass";
  glass.transmittance = transmittance;
  scene.materials.push_back(glass);
  int opaque = -1;
  for (Mesh& m : scene.meshes)
    if (m.name != "ground") {
      opaque = m.material;
      m.material = static_cast<int>(scene.materials.size() - 1);
    }
  Mesh ball = make_sphere(Vec3(0.2f, 1.2f, 0.6f), 0.2f, 12, 24);
  ball.name = "opaque_ball";
  ball.material = opaque;
  scene.meshes.push_back(std::move(ball));
  return scene;
}

/// §4.3.3: semi-opaque spheres and an opaque ball, the exact product and the paper's sum.
TEST(VulkanDcs, SemiOpaqueOccluders) {
  PENUMBRA_VULKAN_BACKEND_OR_SKIP(backend);
  const auto t =
      make_test_frame(semi_opaque(make_builtin_scene("spheres"), 0.3f), 40, 40, grid_samples(8));
  check_frame(backend, t, "semi-opaque product", {}, false, 0);
  check_frame(backend, t, "semi-opaque paper", {{"semi_opaque", "paper"}}, false, 0);
}

/// A semi-opaque alpha-textured fence (`default`): its S-triangles step their own layer class.
TEST(VulkanDcs, SemiOpaqueTexturedOccluder) {
  PENUMBRA_VULKAN_BACKEND_OR_SKIP(backend);
  Scene scene = make_builtin_scene("default");
  for (Material& m : scene.materials)
    if (m.alpha_texture >= 0) m.transmittance = 0.5f;
  const auto t = make_test_frame(std::move(scene), 40, 40, grid_samples(8));
  check_frame(backend, t, "semi-opaque fence", {}, false);
  EXPECT_EQ(test::run_vulkan(backend, t, "dcs").per_light[0].counters.at("layer_classes"), 2.0);
}

TEST(VulkanDcs, ReportsGpuStageTimes) {
  PENUMBRA_VULKAN_BACKEND_OR_SKIP(backend);
  const test::TestFrame t = make_test_frame("spheres", 32, 32, grid_samples(4));
  const MethodResult r = test::run_vulkan(backend, t, "dcs");
  const StageTimes& times = r.per_light[0].times;
  for (const char* stage : {"gpu_init", "gpu_edges", "gpu_finish", "wedges", "init"})
    EXPECT_GT(times.get(stage), 0.0) << stage;
  EXPECT_GT(r.per_light[0].counters.at("wedges"), 0.0);
}

/// Per-pixel patterns: each pixel's own samples, sorted into its own bands as the CPU's Sampler
/// sorts them (shared edges, S-triangles and the alpha test read them).
TEST(VulkanDcs, PerPixelPatterns) {
  PENUMBRA_VULKAN_BACKEND_OR_SKIP(backend);
  check_frame(
      backend,
      make_test_frame("spheres", 32, 32, test::sample_spec(SamplePattern::decorrelated, 8, 5)),
      "spheres decorrelated");
  check_frame(backend,
              make_test_frame("fence", 32, 32, test::sample_spec(SamplePattern::interleaved, 8, 5)),
              "fence interleaved");
  check_frame(backend,
              make_test_frame(round_light_scene(LightShape::sphere), 24, 24,
                              test::sample_spec(SamplePattern::decorrelated, 8, 5)),
              "sphere light decorrelated");
  // The host's RGB weighting reads each pixel's own sample positions.
  check_frame(backend,
              make_test_frame(test::with_textured_light(make_builtin_scene("spheres")), 24, 24,
                              test::sample_spec(SamplePattern::interleaved, 8, 5)),
              "textured light interleaved");
}

TEST(VulkanDcs, TooManyCountersIsAClearError) {
  PENUMBRA_VULKAN_BACKEND_OR_SKIP(backend);
  // 1 class × 64² samples × over 2^19 active pixels ≥ 2^31 counters: refused before any device
  // allocation.
  const test::TestFrame t = make_test_frame("quad", 1024, 1024, grid_samples(64));
  try {
    test::run_vulkan(backend, t, "dcs");
    ADD_FAILURE() << "no error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("exceed 2^31"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace penumbra

#else

TEST(VulkanDcs, BuiltWithoutVulkan) {
  GTEST_SKIP() << "built without libvulkan-dev / glslc";
}

#endif
