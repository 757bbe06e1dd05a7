#include "penumbra/gpu/backend.hpp"

#include <algorithm>

#include "penumbra/core/error.hpp"
#include "penumbra/gpu/depth_pass.hpp"
#include "penumbra/gpu/graphics.hpp"

namespace penumbra::gpu {

Backend::Backend(const ContextOptions& options)
    : ctx_(std::make_unique<VulkanContext>(options)),
      programs_(std::make_unique<Programs>(*ctx_)),
      raster_path_(raster_path_for(*ctx_)) {}

Backend::~Backend() = default;

DepthPipeline& Backend::depth_pipeline() {
  if (!depth_) depth_ = std::make_unique<DepthPipeline>(*ctx_, ctx_->has_float64(), raster_path_);
  return *depth_;
}

const GraphicsPipeline& Backend::volume_pipeline() {
  if (!volume_) {
    // Its setup and per-pixel tests are the CPU's, in double.
    if (!ctx_->has_float64())
      throw Error("shadow_volume on Vulkan needs shaderFloat64, which " + ctx_->device_name() +
                  " lacks");
    GraphicsDesc d;
    d.vert = Shader::volume_vert;
    d.frag = Shader::volume_frag;
    d.push_bytes = 24;
    d.blend_add = true;
    volume_ = std::make_unique<GraphicsPipeline>(*ctx_, d);
  }
  return *volume_;
}

const std::vector<std::string>& Backend::methods() {
  static const std::vector<std::string> names = {"gears",       "dcs",           "shadow_map",
                                                 "pcss",        "shadow_volume", "wedges",
                                                 "wedge_blend", "ssm",           "silhouette_map"};
  return names;
}

bool Backend::supports(std::string_view method) {
  const auto& m = methods();
  return std::find(m.begin(), m.end(), method) != m.end();
}

MethodInfo Backend::vulkan_method(const MethodInfo& info) {
  MethodInfo out = info;
  if (info.name == "gears") {
    out.create = [this](const MethodOptions& o) { return create_gears_vk(*this, o); };
  } else if (info.name == "dcs") {
    out.create = [this](const MethodOptions& o) { return create_dcs_vk(*this, o); };
  } else if (info.name == "wedges") {
    out.create = [this](const MethodOptions& o) { return create_wedges_vk(*this, o); };
  } else if (info.name == "wedge_blend") {
    out.create = [this](const MethodOptions& o) { return create_wedge_blend_vk(*this, o); };
  } else if (info.name == "ssm") {
    out.create = [this](const MethodOptions& o) { return create_ssm_vk(*this, o); };
  } else if (info.name == "silhouette_map") {
    out.create = [this](const MethodOptions& o) { return create_silhouette_map_vk(*this, o); };
  } else if (info.name == "shadow_map") {
    out.create = [this](const MethodOptions& o) { return create_shadow_map_vk(*this, o); };
  } else if (info.name == "pcss") {
    out.create = [this](const MethodOptions& o) { return create_pcss_vk(*this, o); };
  } else if (info.name == "shadow_volume") {
    out.create = [this](const MethodOptions& o) { return create_shadow_volume_vk(*this, o); };
  } else {
    std::string list;
    for (const std::string& n : methods()) list += (list.empty() ? "" : ", ") + n;
    throw Error("method '" + info.name +
                "' has no Vulkan implementation (--backend vulkan runs: " + list + ")");
  }
  return out;
}

}  // namespace penumbra::gpu
