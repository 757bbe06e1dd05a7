// `shadow_map` and `pcss` on Vulkan: the depth map by the graphics pipeline (gpu/depth_pass.hpp),
// the lookup/filter by one compute shader over the G-buffer's active pixels
// (shaders/shadow_lookup.comp) — the CPU methods' settings, bias and filters.
#include <chrono>
#include <cstddef>
#include <deque>

#include "penumbra/core/error.hpp"
#include "penumbra/gpu/backend.hpp"
#include "penumbra/gpu/depth_pass.hpp"
#include "penumbra/render/receivers.hpp"
#include "penumbra/shadows/depth_maps/shadow_map.hpp"
#include "penumbra/shadows/wedges/shadow_volume.hpp"

namespace penumbra::gpu {

namespace {

// shadow_lookup.comp's LookupParams (scalar layout).
struct LookupParams {
  float eye[3];
  float tan_half_x;
  float right[3];
  float tan_half_y;
  float up[3];
  float texel_tan;
  float forward[3];
  int32_t resolution;
  float bias, slope_bias;
  int32_t mode, pcf;
  float light_width;
  int32_t blocker_samples, pcf_samples;
  float max_radius;
  // The double copies (shadow_lookup_f64.comp).
  double eye_d[3], right_d[3], up_d[3], forward_d[3];
  double tan_half_x_d, tan_half_y_d, texel_tan_d, bias_d, slope_bias_d, light_width_d, max_radius_d;
};
static_assert(offsetof(LookupParams, eye_d) == 96);

struct LookupPush {
  VkDeviceAddress params, points, map, min_depth, vis;
  uint32_t n;
};

constexpr uint32_t kMinTexelsPerThread = 64;  // depth_min.comp's kTexelsPerThread

struct MinPush {
  VkDeviceAddress depth, result;
  uint32_t n;
};

void put3(float* f, double* d, const DVec3& v) {
  for (int c = 0; c < 3; ++c) f[c] = static_cast<float>(v[c]), d[c] = v[c];
}

class DepthMapVk final : public ShadowMethod {
 public:
  DepthMapVk(Backend& backend, const MethodOptions& o, bool pcss)
      : backend_(backend), settings_(DepthMapSettings::from(o)), pcss_(pcss) {
    if (pcss) {
      blocker_ = o.get_int("blocker_samples");
      pcf_samples_ = o.get_int("pcf_samples");
      max_radius_ = o.get_real("max_radius");
      light_size_ = o.get_real("light_size");
    } else {
      pcf_ = o.get_int("pcf");
    }
  }

  Visibility compute(const ShadowContext& ctx) override {
    VulkanContext& vk = backend_.context();
    const GBuffer& g = ctx.gbuffer;
    Visibility vis;
    vis.lit = Image<float>(g.width, g.height, 1.0f);

    auto t0 = std::chrono::steady_clock::now();
    const auto [active, cover, points] = lookup_points(g, ctx.receivers);
    std::deque<Buffer> keep;
    std::deque<Image2D> images;
    keep.push_back(vk.upload(points));
    const Buffer& point_buf = keep.back();
    const Buffer vis_buf(vk, std::max<size_t>(active.size(), 1) * sizeof(float), Memory::device);
    const Buffer min_buf(vk, sizeof(uint32_t), Memory::device);
    vis.times.add("wall_upload", elapsed_ms(t0));

    t0 = std::chrono::steady_clock::now();
    CommandList cl(vk);
    DepthMapSpec spec;
    spec.resolution = settings_.resolution;
    spec.faces = settings_.faces;
    const GpuDepthMap map =
        record_depth_map(vk, backend_.depth_pipeline(), cl, ctx.scene, hard_shadow_point(ctx.light),
                         cover, spec, keep, images);
    cl.mark("depth_map");
    const uint32_t texels = static_cast<uint32_t>(map.resolution) * map.resolution;
    cl.fill(min_buf, 0x7f7fffffu);  // FLT_MAX
    cl.barrier();
    if (pcss_) {
      cl.dispatch(backend_.programs().get(Shader::depth_min),
                  MinPush{map.depth.address(), min_buf.address(), texels},
                  (texels + kMinTexelsPerThread - 1) / kMinTexelsPerThread);
      cl.barrier();
      cl.mark("min_depth");
    }
    LookupParams prm{};
    const Projection& pr = map.view.proj;
    put3(prm.eye, prm.eye_d, pr.eye);
    put3(prm.right, prm.right_d, pr.right);
    put3(prm.up, prm.up_d, pr.up);
    put3(prm.forward, prm.forward_d, pr.forward);
    prm.tan_half_x = static_cast<float>(pr.tan_half_x);
    prm.tan_half_y = static_cast<float>(pr.tan_half_y);
    prm.texel_tan = static_cast<float>(map.view.texel_tan);
    prm.resolution = map.resolution;
    prm.bias = static_cast<float>(settings_.bias);
    prm.slope_bias = static_cast<float>(settings_.slope_bias);
    prm.mode = pcss_ ? 1 : 0;
    prm.pcf = pcf_;
    prm.light_width =
        static_cast<float>(light_size_ > 0.0 ? light_size_ : pcss_light_width(ctx.light));
    prm.blocker_samples = blocker_;
    prm.pcf_samples = pcf_samples_;
    prm.max_radius = static_cast<float>(max_radius_);
    prm.tan_half_x_d = pr.tan_half_x, prm.tan_half_y_d = pr.tan_half_y;
    prm.texel_tan_d = map.view.texel_tan;
    prm.bias_d = settings_.bias, prm.slope_bias_d = settings_.slope_bias;
    prm.light_width_d = light_size_ > 0.0 ? light_size_ : pcss_light_width(ctx.light);
    prm.max_radius_d = max_radius_;
    keep.push_back(vk.upload(&prm, sizeof(prm)));
    const uint32_t n = static_cast<uint32_t>(active.size());
    const Shader lookup = vk.has_float64() ? Shader::shadow_lookup_f64 : Shader::shadow_lookup;
    cl.dispatch(backend_.programs().get(lookup),
                LookupPush{keep.back().address(), point_buf.address(), map.depth.address(),
                           min_buf.address(), vis_buf.address(), n},
                n);
    cl.barrier();
    cl.mark(pcss_ ? "filter" : "lookup");
    cl.submit(&vis.times);
    vis.times.add("wall_gpu", elapsed_ms(t0));

    t0 = std::chrono::steady_clock::now();
    const std::vector<float> v = vk.download<float>(vis_buf, active.size());
    for (size_t a = 0; a < active.size(); ++a) vis.lit[active[a]] = v[a];
    vis.times.add("wall_readback", elapsed_ms(t0));
    vis.counters["map_texel_tan"] = map.view.texel_tan;
    if (pcss_) vis.counters["light_width"] = prm.light_width;
    return vis;
  }

 private:
  Backend& backend_;
  DepthMapSettings settings_;
  bool pcss_;
  int pcf_ = 1, blocker_ = 6, pcf_samples_ = 8;
  double max_radius_ = 64.0, light_size_ = 0.0;
};

}  // namespace

std::unique_ptr<ShadowMethod> create_shadow_map_vk(Backend& backend, const MethodOptions& options) {
  return std::make_unique<DepthMapVk>(backend, options, false);
}

std::unique_ptr<ShadowMethod> create_pcss_vk(Backend& backend, const MethodOptions& options) {
  return std::make_unique<DepthMapVk>(backend, options, true);
}

}  // namespace penumbra::gpu
