// `wedge_blend` on Vulkan: penumbra-wedge blending [Forest 2008 §3.2, Algorithms 4–6, eq. 3.1,
// §3.3.3] with the per-pixel SV-buffers and their blend in a compute shader
// (shaders/wedge_blend_pass2.comp). The CPU method's own code does the rest (wedge_blend.hpp
// make_wedge_blend with a pass-2 hook): the caster groups and silhouettes from the light centre,
// each group's hard count, the wedges and their tile bins, and the soft textured shadow volumes'
// V_coef. The per-pixel arithmetic is the CPU's, in double and in bin order; the sector angles
// come from a double atan2 written in GLSL (it has none), within a few ulps of the CPU's.
#include <algorithm>

#include "penumbra/core/error.hpp"
#include "penumbra/gpu/backend.hpp"
#include "penumbra/gpu/wedge_data.hpp"
#include "penumbra/gpu/wedge_pixels.hpp"
#include "penumbra/shadows/wedges/wedge_blend.hpp"

namespace penumbra::gpu {

namespace {

struct BlendPush {
  VkDeviceAddress pix, wedges, weight, wedge_group, bin_begin, bin_entries, count_begin,
      count_group, count_value, lit;
  uint32_t na;
};
static_assert(sizeof(BlendPush) <= kPushBytes);

/// V per pixel of ctx.light from the groups' hard counts and the binned wedges.
Image<float> blend_pass(Backend& backend, const ShadowContext& ctx,
                        const wedge_pass::BinnedWedges& bw, const wedge_pass::GroupCounts& gc) {
  VulkanContext& vk = backend.context();
  const GBuffer& g = ctx.gbuffer;
  const std::vector<WedgePixelGpu> pixels = wedge_pixels(ctx, ctx.light, bw.tiles_x);
  const uint32_t na = static_cast<uint32_t>(pixels.size());
  Image<float> vis(g.width, g.height, 1.0f);
  if (na == 0) return vis;
  std::vector<WedgeGpu> wedges;
  std::vector<double> weight;
  for (const Wedge& w : bw.wedges) {
    wedges.push_back(to_gpu(w, 0));
    weight.push_back(w.weight);
  }
  // Empty arrays still need a buffer to address.
  const auto nonempty = [](auto v) {
    if (v.empty()) v.emplace_back();
    return v;
  };
  const Bins bins(bw.bins);
  const Buffer pix_buf = vk.upload(pixels);
  const Buffer wedge_buf = vk.upload(nonempty(wedges));
  const Buffer weight_buf = vk.upload(nonempty(weight));
  const Buffer group_buf = vk.upload(nonempty(bw.group));
  const Buffer begin_buf = vk.upload(bins.begin);
  const Buffer entry_buf = vk.upload(nonempty(bins.entries));
  const Buffer count_begin = vk.upload(gc.begin);
  const Buffer count_group = vk.upload(nonempty(gc.group));
  const Buffer count_value = vk.upload(nonempty(gc.value));
  const Buffer lit(vk, static_cast<size_t>(na) * 4, Memory::device);
  CommandList cl(vk);
  cl.dispatch(
      backend.programs().get(Shader::wedge_blend_pass2),
      BlendPush{pix_buf.address(), wedge_buf.address(), weight_buf.address(), group_buf.address(),
                begin_buf.address(), entry_buf.address(), count_begin.address(),
                count_group.address(), count_value.address(), lit.address(), na},
      na);
  cl.mark("pass2_blend");
  cl.submit();
  const std::vector<float> v = vk.download<float>(lit, na);
  for (uint32_t a = 0; a < na; ++a) vis[pixels[a].pixel] = v[a];
  return vis;
}

/// The CPU's `wedge_blend` (same stages and counters) with the per-pixel blend on the device.
class WedgeBlendVk final : public ShadowMethod {
 public:
  WedgeBlendVk(Backend& backend, const MethodOptions& o)
      : backend_(backend),
        method_(
            make_wedge_blend(o, [this](const ShadowContext& ctx, const wedge_pass::BinnedWedges& bw,
                                       const wedge_pass::GroupCounts& gc) {
              return blend_pass(backend_, ctx, bw, gc);
            })) {}

  void prepare(const Scene& scene) override { method_->prepare(scene); }

  Visibility compute(const ShadowContext& ctx) override {
    if (!backend_.context().has_float64())
      throw Error("wedge_blend on vulkan needs shaderFloat64, which " +
                  backend_.context().device_name() + " lacks");
    if (ctx.light.is_textured())
      throw Error("wedge_blend on vulkan: textured lights are not supported (use --backend cpu)");
    return method_->compute(ctx);
  }

 private:
  Backend& backend_;
  std::unique_ptr<ShadowMethod> method_;
};

}  // namespace

std::unique_ptr<ShadowMethod> create_wedge_blend_vk(Backend& backend,
                                                    const MethodOptions& options) {
  return std::make_unique<WedgeBlendVk>(backend, options);
}

}  // namespace penumbra::gpu
