// `wedges` on Vulkan: soft shadow volumes with penumbra wedges [Assarsson 2003 III §3, IV §4–5]
// with pass 2 — per pixel, the coverage of every wedge of its tile that holds it — in a compute
// shader (wedges_pass2.comp). The CPU method's own code does the rest (wedges/wedges.hpp
// make_wedges with WedgeOptions::pass2): the light splitting, the silhouettes from each
// (sub-)light's centre, pass 1's layered hard counts, the wedges and their tile bins, and the
// soft textured shadow volumes' V_coef. The per-pixel sums are the CPU's, in double and in bin
// order; a round light's sector angle comes from the double atan2 of wedge_coverage.glsl.
#include <algorithm>
#include <chrono>

#include "penumbra/core/error.hpp"
#include "penumbra/gpu/backend.hpp"
#include "penumbra/gpu/wedge_data.hpp"
#include "penumbra/gpu/wedge_pixels.hpp"
#include "penumbra/shadows/registry.hpp"
#include "penumbra/shadows/wedges/pass.hpp"
#include "penumbra/shadows/wedges/wedges.hpp"

namespace penumbra::gpu {

namespace {

struct Pass2Push {
  VkDeviceAddress pix, wedges, weight, bin_begin, bin_entries, sum, lit;
  uint32_t na, first, chunk, last;
};
static_assert(sizeof(Pass2Push) <= kPushBytes);

/// Pass 2 of one (sub-)light: V per pixel.
Image<float> pass2(Backend& backend, const ShadowContext& ctx, const Light& light,
                   const wedge_pass::BinnedWedges& bw, const Image<float>& count) {
  VulkanContext& vk = backend.context();
  const GBuffer& g = ctx.gbuffer;
  const std::vector<WedgePixelGpu> pixels = wedge_pixels(ctx, light, bw.tiles_x);
  const uint32_t na = static_cast<uint32_t>(pixels.size());
  std::vector<double> sum(na);
  for (uint32_t a = 0; a < na; ++a) sum[a] = count[pixels[a].pixel];
  std::vector<WedgeGpu> wedges;
  std::vector<double> weight;
  for (const Wedge& w : bw.wedges) {
    wedges.push_back(to_gpu(w, 0));
    weight.push_back(w.weight);
  }
  const Bins bins(bw.bins);

  const Buffer pix_buf = vk.upload(pixels);
  const Buffer wedge_buf = vk.upload(wedges);
  const Buffer weight_buf = vk.upload(weight);
  const Buffer begin_buf = vk.upload(bins.begin);
  const Buffer entry_buf = vk.upload(bins.entries);
  const Buffer sum_buf = vk.upload(sum);
  const Buffer lit(vk, std::max<size_t>(na, 1) * 4, Memory::device);
  Image<float> vis(g.width, g.height, 1.0f);
  if (na == 0) return vis;
  // llvmpipe stops an invocation after 65535 loop iterations (up to 16 planes per wedge); other
  // devices walk a whole bin at once.
  const uint32_t chunk = vk.info().type == "cpu" ? 3000u : std::max(bins.longest, 1u);
  CommandList cl(vk);
  for (uint32_t first = 0;; first += chunk) {
    const bool last = first + chunk >= bins.longest;
    cl.dispatch(backend.programs().get(Shader::wedges_pass2),
                Pass2Push{pix_buf.address(), wedge_buf.address(), weight_buf.address(),
                          begin_buf.address(), entry_buf.address(), sum_buf.address(),
                          lit.address(), na, first, chunk, last ? 1u : 0u},
                na);
    cl.barrier();
    if (last) break;
  }
  cl.mark("pass2");
  cl.submit();
  const std::vector<float> v = vk.download<float>(lit, na);
  for (uint32_t a = 0; a < na; ++a) vis[pixels[a].pixel] = v[a];
  return vis;
}

/// The CPU's `wedges` (same stages, counters and stage times) with pass 2 on the device.
class WedgesVk final : public ShadowMethod {
 public:
  WedgesVk(Backend& backend, const MethodOptions& o) : backend_(backend) {
    WedgeOptions w = wedge_options_of(o);
    if (w.overlap)
      throw Error("wedges.overlap has no Vulkan path (the overlap approximation runs on the CPU)");
    if (w.texture)
      throw Error(
          "wedges.coverage=texture has no Vulkan path (the coverage texture runs on the "
          "CPU)");
    w.pass2 = [this](const ShadowContext& ctx, const Light& light,
                     const wedge_pass::BinnedWedges& bw,
                     const Image<float>& count) { return pass2(backend_, ctx, light, bw, count); };
    method_ = make_wedges(std::move(w));
  }

  Visibility compute(const ShadowContext& ctx) override {
    if (!backend_.context().has_float64())
      throw Error("wedges on vulkan needs shaderFloat64, which " +
                  backend_.context().device_name() + " lacks");
    if (ctx.light.is_textured())
      throw Error("wedges on vulkan: textured lights are not supported (use --backend cpu)");
    return method_->compute(ctx);
  }

 private:
  Backend& backend_;
  std::unique_ptr<ShadowMethod> method_;
};

}  // namespace

std::unique_ptr<ShadowMethod> create_wedges_vk(Backend& backend, const MethodOptions& options) {
  return std::make_unique<WedgesVk>(backend, options);
}

}  // namespace penumbra::gpu
