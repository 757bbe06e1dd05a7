// The Vulkan backend: one device and its pipelines per process, and the methods that have a
// Vulkan path (gears, dcs, shadow_map, pcss, shadow_volume, wedges, wedge_blend, ssm,
// silhouette_map). A GPU method is the CPU method's MethodInfo with create() bound to the device,
// so Frame::run, the comparisons and every metric use it unchanged.
#pragma once

#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "penumbra/gpu/context.hpp"
#include "penumbra/gpu/graphics.hpp"
#include "penumbra/gpu/shaders.hpp"
#include "penumbra/shadows/registry.hpp"

namespace penumbra::gpu {

class DepthPipeline;
class GraphicsPipeline;

class Backend {
 public:
  /// Opens the device (throws Error with a one-line reason when there is none).
  explicit Backend(const ContextOptions& options = {});
  ~Backend();

  VulkanContext& context() { return *ctx_; }
  Programs& programs() { return *programs_; }
  DepthPipeline& depth_pipeline();
  /// The shadow-volume counting pipeline (volume.vert/.frag, additive R32F).
  const GraphicsPipeline& volume_pipeline();
  /// Graphics pipeline or compute for the raster passes (raster_path_for, read once).
  RasterPath raster_path() const { return raster_path_; }

  /// Methods with a Vulkan implementation, in registry order.
  static const std::vector<std::string>& methods();
  static bool supports(std::string_view method);
  /// `info` whose create() builds the Vulkan implementation on this device; throws Error naming
  /// the methods that have one when `info` has none. The Backend must outlive the methods.
  MethodInfo vulkan_method(const MethodInfo& info);

 private:
  std::unique_ptr<VulkanContext> ctx_;
  std::unique_ptr<Programs> programs_;
  std::unique_ptr<DepthPipeline> depth_;
  std::unique_ptr<GraphicsPipeline> volume_;
  RasterPath raster_path_ = RasterPath::graphics;
};

// Factories of the Vulkan methods (gpu/<method>_vk.cpp).
std::unique_ptr<ShadowMethod> create_gears_vk(Backend& backend, const MethodOptions& options);
std::unique_ptr<ShadowMethod> create_dcs_vk(Backend& backend, const MethodOptions& options);
std::unique_ptr<ShadowMethod> create_wedges_vk(Backend& backend, const MethodOptions& options);
std::unique_ptr<ShadowMethod> create_wedge_blend_vk(Backend& backend, const MethodOptions& options);
std::unique_ptr<ShadowMethod> create_ssm_vk(Backend& backend, const MethodOptions& options);
std::unique_ptr<ShadowMethod> create_silhouette_map_vk(Backend& backend,
                                                       const MethodOptions& options);
std::unique_ptr<ShadowMethod> create_shadow_map_vk(Backend& backend, const MethodOptions& options);
std::unique_ptr<ShadowMethod> create_pcss_vk(Backend& backend, const MethodOptions& options);
std::unique_ptr<ShadowMethod> create_shadow_volume_vk(Backend& backend,
                                                      const MethodOptions& options);

}  // namespace penumbra::gpu
