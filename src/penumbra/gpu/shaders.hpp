// The SPIR-V of every shader in shaders/, compiled by glslc at build time and embedded here.
#pragma once

#include <cstdint>
#include <memory>
#include <span>

#include "penumbra/gpu/commands.hpp"

namespace penumbra::gpu {

enum class Shader {
  scan_block,
  scan_add,
  radix_hist,
  radix_scatter,
  radix_scatter_compare,
  gears_cells,
  gears_count,
  gears_write,
  gears_ranges,
  gears_longest,
  gears_raster,
  gears_samples,
  depth_min,
  shadow_lookup,
  shadow_lookup_f64,
  depth_map_vert,
  depth_map_frag,
  depth_map_exact_vert,
  depth_map_exact_frag,
  depth_setup,
  depth_raster,
  volume_setup,
  volume_count,
  volume_vert,
  volume_frag,
  dcs_init,
  dcs_edges,
  dcs_stsv,
  dcs_finish,
  ssm_blend,
  wedges_pass2,
  wedges_pass2_textured,
  wedge_blend_pass2,
  silmap_layer,
  silmap_lookup,
  wedge_blend_pass2_textured,
  count_
};

std::span<const uint32_t> spirv(Shader shader);

/// Compute pipelines of one context, built on first use.
class Programs {
 public:
  explicit Programs(VulkanContext& ctx) : ctx_(ctx) {}
  const ComputePipeline& get(Shader shader);
  VulkanContext& context() const { return ctx_; }

 private:
  VulkanContext& ctx_;
  std::unique_ptr<ComputePipeline> pipelines_[static_cast<int>(Shader::count_)];
};

}  // namespace penumbra::gpu
