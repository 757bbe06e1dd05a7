// Every Vulkan method against its CPU twin on meshes that break heuristics: an open sphere with
// holes and every third triangle flipped plus a non-manifold fin, and the waving flag (a
// deforming open cloth that shadows itself). The sample-exact methods must give the CPU's masks
// (and `raytrace`'s); the others the CPU's visibility.
#include <gtest/gtest.h>

#ifdef PENUMBRA_HAVE_VULKAN

#include <cstdio>
#include <string>

#include "penumbra/scene/animation.hpp"
#include "support/mask_agreement.hpp"
#include "support/vulkan_helpers.hpp"

namespace penumbra {
namespace {

using test::grid_samples;
using test::make_test_frame;

void check_every_method(gpu::Backend& backend, const test::TestFrame& t, const char* name) {
  const MethodResult raytrace = t.run("raytrace", {}, true);
  for (const std::string& method : gpu::Backend::methods()) {
    SCOPED_TRACE(std::string(name) + " " + method);
    const bool masks = MethodRegistry::builtin().get(method).sample_exact;
    const MethodResult cpu = t.run(method, {}, masks);
    const MethodResult gpu = test::run_vulkan(backend, t, method, {}, masks);
    const test::VisibilityDiff dv = test::visibility_diff(t, cpu, gpu);
    const test::VisibilityDiff shadow = test::visibility_diff(t, cpu, cpu, -1.0f, 0.999f);
    std::printf("%s %s: %d active, %d shadowed (V < 0.999), max |dV| %.3g, mean %.3g\n", name,
                method.c_str(), dv.active, shadow.between, dv.max, dv.mean);
    EXPECT_GT(shadow.between, 0) << "the comparison needs shadows";
    // Measured: 0 on every method and both meshes (the GPU runs the CPU's arithmetic).
    EXPECT_EQ(dv.max, 0.0);
    if (masks) {
      EXPECT_EQ(test::compare_masks(t, cpu, gpu, false).differ, 0u);
      test::expect_equal_masks(test::compare_masks(t, raytrace, gpu));
    }
  }
  EXPECT_EQ(backend.context().validation_messages(), 0u);
}

TEST(VulkanMeshes, OpenFlippedNonManifoldMesh) {
  PENUMBRA_VULKAN_BACKEND_OR_SKIP(backend);
  check_every_method(backend,
                     make_test_frame(test::open_non_manifold_scene(), 40, 40, grid_samples(8)),
                     "open non-manifold");
}

TEST(VulkanMeshes, WavingFlagShadowsItself) {
  PENUMBRA_VULKAN_BACKEND_OR_SKIP(backend);
  const Scene rest = make_builtin_scene("flag");
  check_every_method(backend, make_test_frame(pose_scene(rest, 0.5), 40, 40, grid_samples(8)),
                     "flag");
}

}  // namespace
}  // namespace penumbra

#else

TEST(VulkanMeshes, BuiltWithoutVulkan) {
  GTEST_SKIP() << "built without libvulkan-dev / glslc";
}

#endif
