// The light-space depth map on the GPU: the casters drawn by the graphics pipeline into a
// square R32F view-depth target (depth-only work: the colour target stores the nearest caster's
// view depth, the D32 attachment does the test) in the frustum of fit_depth_map_view, then copied
// into a buffer the lookup shaders read. Same projection, near plane and face selection as the
// CPU's render_depth_map; the rasterization rule is Vulkan's (sample at the texel centre,
// top-left rule) — the CPU's too, up to float instead of double vertex arithmetic.
#pragma once

#include <deque>

#include "penumbra/gpu/commands.hpp"
#include "penumbra/raster/depth_map.hpp"
#include "penumbra/scene/scene.hpp"

namespace penumbra::gpu {

/// The graphics pipeline of the depth pass (cull mode set per draw). Where the device has
/// shaderFloat64 the fragment shader recomputes each texel's depth in double at the texel centre,
/// as the CPU rasterizer does, so the two maps agree to the float.
class DepthPipeline {
 public:
  explicit DepthPipeline(VulkanContext& ctx);
  ~DepthPipeline();
  DepthPipeline(const DepthPipeline&) = delete;
  DepthPipeline& operator=(const DepthPipeline&) = delete;
  VkPipeline handle() const { return pipeline_; }
  VkPipelineLayout layout() const { return layout_; }
  /// Depth recomputed in double per texel (depth_map_f64.frag).
  bool float64() const { return float64_; }

 private:
  VkDevice device_;
  bool float64_ = false;
  VkPipelineLayout layout_ = VK_NULL_HANDLE;
  VkPipeline pipeline_ = VK_NULL_HANDLE;
};

/// A device image with its memory and view. Move-only.
class Image2D {
 public:
  Image2D(VulkanContext& ctx, int width, int height, VkFormat format, VkImageUsageFlags usage,
          VkImageAspectFlags aspect);
  ~Image2D();
  Image2D(const Image2D&) = delete;
  Image2D& operator=(const Image2D&) = delete;
  VkImage image() const { return image_; }
  VkImageView view() const { return view_; }

 private:
  VkDevice device_;
  VkImage image_ = VK_NULL_HANDLE;
  VkDeviceMemory memory_ = VK_NULL_HANDLE;
  VkImageView view_ = VK_NULL_HANDLE;
};

/// Empty texels hold FLT_MAX (the CPU map's +inf: never nearer than a receiver).
inline constexpr float kEmptyDepth = 3.40282347e38f;

struct GpuDepthMap {
  DepthMapView view;
  int resolution = 0;
  Buffer depth;  // resolution² floats, row-major, row 0 at the top (the CPU map's layout)
  size_t triangles = 0;
};

/// Records the depth map of ctx's casters from `light_point` into `cl`. Buffers and images the
/// submission needs go to `keep`/`images`, which must outlive it.
GpuDepthMap record_depth_map(VulkanContext& ctx, DepthPipeline& pipe, CommandList& cl,
                             const Scene& scene, const Vec3& light_point,
                             std::span<const Vec3> cover, const DepthMapSpec& spec,
                             std::deque<Buffer>& keep, std::deque<Image2D>& images);

}  // namespace penumbra::gpu
