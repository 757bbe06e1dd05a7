// Graphics-pipeline building blocks of the raster passes (depth maps, shadow volumes): a pipeline
// with one optional R32 colour target (written or additively blended) and an optional D32 depth
// test, driven by vertex pulling (no vertex input: shaders read their geometry from buffer device
// addresses in push constants), dynamic rendering; images and layout barriers.
#pragma once

#include <cstdint>

#include "penumbra/gpu/commands.hpp"
#include "penumbra/gpu/context.hpp"
#include "penumbra/gpu/shaders.hpp"

namespace penumbra::gpu {

/// How the raster passes (the exact depth map, the shadow-volume count) find their pixels: the
/// graphics pipeline draws candidate boxes and a fragment shader tests them, or a compute shader
/// walks the same boxes (devices with few graphics units) — the same results either way.
enum class RasterPath { graphics, compute };

/// $PENUMBRA_VK_RASTER (`graphics` or `compute`, else an Error), or by default `compute` on the
/// data-centre GPUs without a display engine (device names with H100, H200, H800, H20, A100,
/// A800, A30, B100, B200, GH200: fragment work measured ~30× slower than compute there) and
/// `graphics` elsewhere.
RasterPath raster_path_for(const VulkanContext& ctx);

/// Push constants of a graphics pipeline: vertex and fragment stages.
inline constexpr VkShaderStageFlags kGraphicsPushStages =
    VK_SHADER_STAGE_VERTEX_BIT | VK_SHADER_STAGE_FRAGMENT_BIT;

struct GraphicsDesc {
  Shader vert = Shader::count_, frag = Shader::count_;
  uint32_t push_bytes = 0;
  VkFormat color = VK_FORMAT_R32_SFLOAT;
  bool blend_add = false;  // colour = colour + fragment (ONE, ONE): order-independent counts
  VkFormat depth = VK_FORMAT_UNDEFINED;  // none
  VkCompareOp depth_op = VK_COMPARE_OP_ALWAYS;
};

/// Viewport, scissor, cull mode and front face are dynamic.
class GraphicsPipeline : public Pipeline {
 public:
  GraphicsPipeline(VulkanContext& ctx, const GraphicsDesc& desc);
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

/// A full barrier that moves `image` from layout `from` to `to`.
void image_barrier(VkCommandBuffer cmd, VkImage image, VkImageAspectFlags aspect,
                   VkImageLayout from, VkImageLayout to);

/// Starts dynamic rendering into `color` (R32, cleared to `clear`) and optionally `depth` (D32,
/// cleared to `depth_clear`), both width × height and moved to attachment layout first; viewport
/// and scissor cover the target, front faces are counter-clockwise, nothing is culled.
void begin_rendering(VkCommandBuffer cmd, const Image2D& color, float clear, const Image2D* depth,
                     float depth_clear, int width, int height);
/// Ends rendering and copies `color` (width × height, 4-byte texels) into `dst`, row-major.
void end_rendering_into(VkCommandBuffer cmd, const Image2D& color, int width, int height,
                        const Buffer& dst);

}  // namespace penumbra::gpu
