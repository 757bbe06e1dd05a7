// `silhouette_map` on Vulkan against the CPU method on the same frame: the depth map from the
// Vulkan depth pass, the silhouette layer and the eq. 4 lookup in compute shaders [Valient 2005
// §2]. The GPU merges each texel's candidates in the CPU's face order and computes in double, so V
// is equal on every pixel: rect, disk and sphere lights, hard and soft modes, the alpha fence (its
// bars opaque on both), an open non-manifold mesh, non-default options; unknown options are a
// clear error.
#include <gtest/gtest.h>

#ifdef PENUMBRA_HAVE_VULKAN

#include <cstdio>

#include "penumbra/core/error.hpp"
#include "penumbra/render/receivers.hpp"
#include "support/vulkan_helpers.hpp"

namespace penumbra {
namespace {

using test::grid_samples;
using test::make_test_frame;
using test::round_light_scene;

/// GPU silhouette_map against the CPU's on one frame: V equal on every active pixel (measured: no
/// pixel differs in any case below), the same silhouette faces, band and texels evaluated.
void check_frame(gpu::Backend& backend, const test::TestFrame& t, const std::string& name,
                 std::map<std::string, std::string> options = {}, int min_between = 10) {
  SCOPED_TRACE(name);
  options.emplace("resolution", "128");
  const MethodResult gpu = test::run_vulkan(backend, t, "silhouette_map", options);
  const MethodResult cpu = t.run("silhouette_map", options);
  const Visibility &g = gpu.per_light[0], &c = cpu.per_light[0];
  const test::VisibilityDiff d = test::visibility_diff(t, cpu, gpu, 1e-6f, 1.0f - 1e-6f);
  int differ = 0, shadowed = 0;
  for (size_t i = 0; i < c.lit.size(); ++i) {
    if (t.frame->receivers(0)[i] != kActive) continue;
    differ += c.lit[i] != g.lit[i];
    shadowed += c.lit[i] < 1.0f;
  }
  std::printf(
      "%s: %d active, %d shadowed, %d in (0, 1), %d differ, max |dV| %.3g, mean %.3g, "
      "%g silhouette faces, %g texels\n",
      name.c_str(), d.active, shadowed, d.between, differ, d.max, d.mean,
      g.counters.at("silhouette_faces"), g.counters.at("silhouette_texels"));
  EXPECT_GT(shadowed, 50) << "the comparison needs shadows";
  EXPECT_GT(d.between, min_between) << "and shadow boundaries";
  EXPECT_EQ(differ, 0);
  EXPECT_LE(d.mean, 1e-6);
  for (const char* k : {"tam_faces", "silhouette_faces", "corrected_faces", "duplicate_faces",
                        "silhouette_texels", "half_band_texels"})
    EXPECT_EQ(g.counters.at(k), c.counters.at(k)) << k;
  EXPECT_EQ(backend.context().validation_messages(), 0u);
}

TEST(VulkanSilhouetteMap, RectLightHardAndSoft) {
  PENUMBRA_VULKAN_BACKEND_OR_SKIP(backend);
  const auto t = make_test_frame("spheres", 48, 48, grid_samples(1));
  check_frame(backend, t, "spheres rect hard");
  check_frame(backend, t, "spheres rect soft", {{"mode", "soft"}});
  check_frame(backend, make_test_frame("quad", 48, 48, grid_samples(1)), "quad rect soft",
              {{"mode", "soft"}});
}

TEST(VulkanSilhouetteMap, DiskAndSphereLightsHardAndSoft) {
  PENUMBRA_VULKAN_BACKEND_OR_SKIP(backend);
  for (LightShape shape : {LightShape::disk, LightShape::sphere}) {
    const auto t = make_test_frame(round_light_scene(shape), 40, 40, grid_samples(1));
    const std::string name = shape == LightShape::disk ? "disk" : "sphere";
    check_frame(backend, t, name + " hard");
    check_frame(backend, t, name + " soft", {{"mode", "soft"}});
  }
}

TEST(VulkanSilhouetteMap, FenceBarsOpaqueAsOnCpu) {
  PENUMBRA_VULKAN_BACKEND_OR_SKIP(backend);
  const auto t = make_test_frame("fence", 48, 48, grid_samples(1));
  check_frame(backend, t, "fence hard");
  check_frame(backend, t, "fence soft", {{"mode", "soft"}});
}

TEST(VulkanSilhouetteMap, OpenNonManifoldMesh) {
  PENUMBRA_VULKAN_BACKEND_OR_SKIP(backend);
  const auto t = make_test_frame(test::open_non_manifold_scene(), 48, 48, grid_samples(1));
  check_frame(backend, t, "open hard");
  check_frame(backend, t, "open soft", {{"mode", "soft"}});
}

TEST(VulkanSilhouetteMap, OtherOptions) {
  PENUMBRA_VULKAN_BACKEND_OR_SKIP(backend);
  const auto t = make_test_frame("spheres", 48, 48, grid_samples(1));
  check_frame(backend, t, "step, offset, wide band, both faces",
              {{"aa_width", "0"}, {"offset", "0.5"}, {"width", "6"}, {"faces", "both"}},
              -1);  // a step: no V strictly between 0 and 1
  check_frame(backend, t, "bias, narrow soft band",
              {{"bias", "0.01"},
               {"slope_bias", "1"},
               {"mode", "soft"},
               {"max_band", "3"},
               {"resolution", "96"}});
}

TEST(VulkanSilhouetteMap, UnknownOptionsAreClearErrors) {
  PENUMBRA_VULKAN_BACKEND_OR_SKIP(backend);
  const auto t = make_test_frame("quad", 16, 16, grid_samples(1));
  EXPECT_THROW(test::run_vulkan(backend, t, "silhouette_map", {{"mode", "medium"}}), Error);
  EXPECT_THROW(test::run_vulkan(backend, t, "silhouette_map", {{"pcf", "3"}}), Error);
}

}  // namespace
}  // namespace penumbra

#else

TEST(VulkanSilhouetteMap, BuiltWithoutVulkan) {
  GTEST_SKIP() << "built without libvulkan-dev / glslc";
}

#endif
