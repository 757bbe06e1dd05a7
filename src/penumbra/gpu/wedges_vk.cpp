// `wedges` on Vulkan: soft shadow volumes with penumbra wedges [Assarsson 2003 III §3, IV §4–5]
// with pass 2 — per pixel, the coverage of every wedge of its tile that holds it — in a compute
// shader (wedges_pass2.comp). The CPU method's own code does the rest (wedges/wedges.hpp
// make_wedges with WedgeOptions::pass2): the light splitting (and a textured light's sub-textures),
// the silhouettes from each (sub-)light's centre, pass 1's hard counts (layered, or per caster
// group for the overlap approximation), the wedges and their tile bins, V from the per-channel
// occlusion, and the soft textured shadow volumes' V_coef. The per-pixel sums and their overlap
// fold are the CPU's, in double and in bin order; a round light's sector angle comes from the
// double atan2 of wedge_coverage.glsl, a textured light's per-channel coverage from
// wedge_emission.glsl.
#include <algorithm>
#include <string>
#include <vector>

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
  VkDeviceAddress pix, wedges, weight, wedge_group, bin_begin, bin_entries, count_begin,
      count_group, count_value, state, density, table;
  uint32_t na, first, chunk, mode;
  int32_t em_w, em_h;
  uint32_t table_n, pad;
};
static_assert(sizeof(Pass2Push) <= kPushBytes);

/// wedges_pass2.glsl State: the open group's sum, the folded total, the open group, next count.
struct PassState {
  double sum[3], total[3];
  uint32_t grp, ci;
};
static_assert(sizeof(PassState) == 56);
constexpr uint32_t kLast = 2, kFirst = 4, kTable = 8, kQuadrilinear = 16;

/// Bin entries per dispatch. llvmpipe stops an invocation after 65535 loop iterations in all: a
/// wedge costs up to ~60 (16 planes, the clips, the sector, the angle's series) and, with a
/// textured light, up to 80 per texel its region reaches (wedge_emission.glsl weigh_polygon: the
/// region has at most 6 vertices, at most 10 after a texel's four clips, so four clip loops of
/// 13–19 iterations and the area's 10). Other devices walk a whole bin at once.
uint32_t chunk_of(const VulkanContext& vk, const LightEmission* emission, uint32_t longest) {
  if (vk.info().type != "cpu") return std::max(longest, 1u);
  const uint64_t texels = emission ? static_cast<uint64_t>(emission->width) * emission->height : 0u;
  const uint64_t per_wedge = 60 + 80 * texels;
  if (per_wedge > 60000)
    throw Error("wedges on vulkan: a " + std::to_string(emission->width) + "x" +
                std::to_string(emission->height) +
                " light texture exceeds lavapipe's loop limit (use --backend cpu)");
  return std::max(1u, static_cast<uint32_t>(60000 / per_wedge));
}

/// Pass 2 of one (sub-)light: per active pixel the folded occlusion per channel.
Image<DVec3> pass2(Backend& backend, const ShadowContext& ctx, const Light& light,
                   const WedgePass2Input& in) {
  VulkanContext& vk = backend.context();
  const GBuffer& g = ctx.gbuffer;
  const wedge_pass::BinnedWedges& bw = in.wedges;
  const wedge_pass::GroupCounts& gc = in.counts;
  Image<DVec3> occ(g.width, g.height, DVec3(0.0));
  const std::vector<WedgePixelGpu> pixels = wedge_pixels(ctx, light, bw.tiles_x);
  const uint32_t na = static_cast<uint32_t>(pixels.size());
  if (na == 0) return occ;
  std::vector<WedgeGpu> wedges;
  std::vector<double> weight;
  for (const Wedge& w : bw.wedges) {
    wedges.push_back(to_gpu(w, 0));
    weight.push_back(w.weight);
  }
  std::vector<uint32_t> group = in.grouped ? bw.group : std::vector<uint32_t>(bw.wedges.size(), 0);
  std::vector<DVec3> density{DVec3(0.0)};
  int32_t em_w = 1, em_h = 1;
  if (in.emission) {
    density = in.emission->density;
    em_w = in.emission->width, em_h = in.emission->height;
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
  const Buffer group_buf = vk.upload(nonempty(group));
  const Buffer begin_buf = vk.upload(bins.begin);
  const Buffer entry_buf = vk.upload(nonempty(bins.entries));
  const Buffer count_begin = vk.upload(gc.begin);
  const Buffer count_group = vk.upload(nonempty(gc.group));
  const Buffer count_value = vk.upload(nonempty(gc.value));
  const Buffer state_buf(vk, static_cast<size_t>(na) * sizeof(PassState), Memory::device);
  const Buffer density_buf = vk.upload(density);
  const Buffer table_buf = vk.upload(in.table ? in.table->entries() : std::vector<float>{0.0f});
  uint32_t table_mode = 0;
  if (in.table)
    table_mode = kTable | (in.lookup == CoverageTexture::Lookup::quadrilinear ? kQuadrilinear : 0u);
  const uint32_t chunk = chunk_of(vk, in.emission, bins.longest);
  const Shader shader = in.emission ? Shader::wedges_pass2_textured : Shader::wedges_pass2;
  CommandList cl(vk);
  for (uint32_t first = 0;; first += chunk) {
    const bool last = first + chunk >= bins.longest;
    cl.dispatch(backend.programs().get(shader),
                Pass2Push{pix_buf.address(),
                          wedge_buf.address(),
                          weight_buf.address(),
                          group_buf.address(),
                          begin_buf.address(),
                          entry_buf.address(),
                          count_begin.address(),
                          count_group.address(),
                          count_value.address(),
                          state_buf.address(),
                          density_buf.address(),
                          table_buf.address(),
                          na,
                          first,
                          chunk,
                          table_mode | (first == 0 ? kFirst : 0u) | (last ? kLast : 0u),
                          em_w,
                          em_h,
                          in.table ? static_cast<uint32_t>(in.table->n()) : 0u,
                          0u},
                na);
    cl.barrier();
    if (last) break;
  }
  cl.mark("pass2");
  cl.submit();
  const std::vector<PassState> out = vk.download<PassState>(state_buf, na);
  for (uint32_t a = 0; a < na; ++a)
    occ[pixels[a].pixel] = DVec3(out[a].total[0], out[a].total[1], out[a].total[2]);
  return occ;
}

/// The CPU's `wedges` (same stages, counters and stage times) with pass 2 on the device.
class WedgesVk final : public ShadowMethod {
 public:
  WedgesVk(Backend& backend, const MethodOptions& o) : backend_(backend) {
    WedgeOptions w = wedge_options_of(o);
    texture_ = w.texture;
    w.pass2 = [this](const ShadowContext& ctx, const Light& light, const WedgePass2Input& in) {
      return pass2(backend_, ctx, light, in);
    };
    method_ = make_wedges(std::move(w));
  }

  Visibility compute(const ShadowContext& ctx) override {
    if (!backend_.context().has_float64())
      throw Error("wedges on vulkan needs shaderFloat64, which " +
                  backend_.context().device_name() + " lacks");
    if (texture_ && ctx.light.shape == LightShape::rect && ctx.light.is_textured())
      throw Error(
          "wedges.coverage=texture with a textured light has no Vulkan path (the RGB coverage "
          "texture runs on the CPU)");
    return method_->compute(ctx);
  }

  void prepare(const Scene& scene) override { method_->prepare(scene); }

 private:
  Backend& backend_;
  bool texture_ = false;
  std::unique_ptr<ShadowMethod> method_;
};

}  // namespace

std::unique_ptr<ShadowMethod> create_wedges_vk(Backend& backend, const MethodOptions& options) {
  return std::make_unique<WedgesVk>(backend, options);
}

}  // namespace penumbra::gpu
