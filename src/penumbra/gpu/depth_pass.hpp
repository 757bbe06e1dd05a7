// The light-space depth map on the GPU: the casters drawn by the graphics pipeline into a
// square R32F view-depth target (depth-only work: the colour target stores the nearest caster's
// view depth, the D32 attachment does the test) in the frustum of fit_depth_map_view, then copied
// into a buffer the lookup shaders read. Same projection, near plane and face selection as the
// CPU's render_depth_map. With shaderFloat64 the pass is exact: a compute setup pass clips and
// projects each caster in double as the CPU does, the rasterizer only generates candidate texels
// (the polygon's pixel box) and the fragment shader applies the CPU rasterizer's edge functions,
// top-left rule and 1/w interpolation — the two maps are equal texel for texel. Without it,
// hardware coverage (float vertices snapped to the sub-texel grid) may differ at caster edges.
#pragma once

#include <deque>
#include <memory>
#include <vector>

#include "penumbra/gpu/commands.hpp"
#include "penumbra/gpu/graphics.hpp"
#include "penumbra/raster/depth_map.hpp"
#include "penumbra/render/gbuffer.hpp"
#include "penumbra/scene/scene.hpp"

namespace penumbra::gpu {

/// The pipelines of the depth pass: the exact pass (depth_exact.glsl, with its setup compute
/// pipeline; drawn, or rasterized in compute) where the device has shaderFloat64, else hardware
/// coverage (cull mode set per draw).
class DepthPipeline {
 public:
  /// `exact` needs shaderFloat64 (VulkanContext::has_float64); `raster` applies to the exact pass
  /// (RasterPath::compute: depth_raster.comp).
  DepthPipeline(VulkanContext& ctx, bool exact, RasterPath raster = RasterPath::graphics);
  ~DepthPipeline();
  DepthPipeline(const DepthPipeline&) = delete;
  DepthPipeline& operator=(const DepthPipeline&) = delete;
  VkPipeline handle() const { return graphics_->handle(); }
  VkPipelineLayout layout() const { return graphics_->layout(); }
  /// The exact pass (depth_setup.comp + depth_map_exact.*).
  bool exact() const { return exact_; }
  const ComputePipeline& setup() const { return *setup_; }
  /// The exact pass rasterized in compute (depth_raster.comp): no graphics work at all.
  bool compute() const { return static_cast<bool>(raster_); }
  const ComputePipeline& raster() const { return *raster_; }

 private:
  bool exact_ = false;
  std::unique_ptr<GraphicsPipeline> graphics_;
  std::unique_ptr<ComputePipeline> setup_, raster_;
};

/// Empty texels hold FLT_MAX (the CPU map's +inf: never nearer than a receiver).
inline constexpr float kEmptyDepth = 3.40282347e38f;

struct GpuDepthMap {
  DepthMapView view;
  int resolution = 0;
  Buffer depth;  // resolution² floats, row-major, row 0 at the top (the CPU map's layout)
  size_t triangles = 0;
};

/// The receivers a depth-map lookup shades: the G-buffer's active pixels, their shadow origins
/// (the map's cover), and per receiver its origin and geometric normal as the shaders read them.
struct LookupPoints {
  std::vector<uint32_t> active;
  std::vector<Vec3> cover;
  std::vector<float> points;  // x, y, z, 0, normal x, y, z, 0 per receiver
};
LookupPoints lookup_points(const GBuffer& g, const Image<uint8_t>& receivers);

/// Records the depth map of ctx's casters from `light_point` into `cl`. Buffers and images the
/// submission needs go to `keep`/`images`, which must outlive it.
GpuDepthMap record_depth_map(VulkanContext& ctx, DepthPipeline& pipe, CommandList& cl,
                             const Scene& scene, const Vec3& light_point,
                             std::span<const Vec3> cover, const DepthMapSpec& spec,
                             std::deque<Buffer>& keep, std::deque<Image2D>& images);

}  // namespace penumbra::gpu
