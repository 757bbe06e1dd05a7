// `wedge_blend` on Vulkan: penumbra-wedge blending [Forest 2008 §3.2, Algorithms 4–6, eq. 3.1,
// §3.3.3] with the per-pixel SV-buffers and their blend in a compute shader
// (shaders/wedge_blend_pass2.glsl). The CPU method's own code does the rest (wedge_blend.hpp
// make_wedge_blend with a pass-2 hook): the caster groups and silhouettes from the light centre,
// each group's hard count, the wedges and their tile bins, a textured light's emission and part
// shares, V from the per-channel occlusion, and the soft textured shadow volumes' V_coef. The
// per-pixel arithmetic is the CPU's, in double and in bin order; the sector angles come from a
// double atan2 written in GLSL (it has none), within a few ulps of the CPU's, and a textured
// light's shares from wedge_emission.glsl.
#include <algorithm>
#include <string>
#include <vector>

#include "penumbra/core/error.hpp"
#include "penumbra/gpu/backend.hpp"
#include "penumbra/gpu/wedge_data.hpp"
#include "penumbra/gpu/wedge_pixels.hpp"
#include "penumbra/shadows/wedges/wedge_blend.hpp"

namespace penumbra::gpu {

namespace {

struct BlendPush {
  VkDeviceAddress pix, wedges, weight, wedge_group, bin_begin, bin_entries, run_end, count_begin,
      count_group, count_value, state, occ, part, density;
  uint32_t na, budget, costs, em_size;
};
static_assert(sizeof(BlendPush) <= kPushBytes);

/// wedge_blend_pass2.glsl SvPart and State: the V-buffer, the open group's SV-buffer and the
/// walk's cursors.
struct SvPartGpu {
  double occ[3], rect[4];
  double outer_s, outer_t, inner_s, inner_t, inner_angle;
};
struct BlendState {
  double v_occ[4][3];
  double v_rect[4][4];
  SvPartGpu sv[4];
  uint32_t ci, bi, bj, j, phase, pad;
};
static_assert(sizeof(BlendState) == 632);
constexpr uint32_t kFirst = 1u << 30, kStore = 1u << 31;  // BlendPush::costs, above the costs

/// Per bin entry (CSR position) the end of the run of its group's entries in its bin.
std::vector<uint32_t> run_ends(const Bins& bins, const std::vector<uint32_t>& group) {
  std::vector<uint32_t> end(bins.entries.size());
  for (size_t t = 0; t + 1 < bins.begin.size(); ++t)
    for (uint32_t j = bins.begin[t], k = j; j < bins.begin[t + 1]; j = k) {
      k = j + 1;
      while (k < bins.begin[t + 1] && group[bins.entries[k]] == group[bins.entries[j]]) ++k;
      std::fill(end.begin() + j, end.begin() + k, k);
    }
  return end;
}

/// The loop iterations a dispatch may spend per pixel. llvmpipe stops an invocation after 65535
/// loop iterations in all; the walk goes in steps — open a group (~50), one bin entry of one pass
/// (~250 with no loop unrolled: the wedge test, the clips, the sectors and angles of the parts it
/// reaches), close the group. A
/// textured light adds to an entry's step up to 80 per texel a part's region reaches
/// (wedge_emission.glsl weigh_polygon, as in wedges_vk.cpp), in at most three parts, and to a
/// group's step one per texel of three rectangles in each of the four parts. A part reaches at
/// most (⌊w/2⌋ + 1) × (⌊h/2⌋ + 1) texels. Other devices walk every pixel's bin in one dispatch.
struct Budget {
  uint32_t budget = 0xffffffffu, entry_cost = 0, group_cost = 0;
};
Budget budget_of(const VulkanContext& vk, const LightEmission* emission) {
  if (vk.info().type != "cpu") return {};
  const uint64_t part_texels =
      emission ? static_cast<uint64_t>(emission->width / 2 + 1) * (emission->height / 2 + 1) : 0u;
  const uint64_t entry = 250 + 3 * 80 * part_texels, group = 50 + 12 * part_texels;
  if (entry > 59000 || group > 16000)
    throw Error("wedge_blend on vulkan: a " + std::to_string(emission->width) + "x" +
                std::to_string(emission->height) +
                " light texture exceeds lavapipe's loop limit (use --backend cpu)");
  return Budget{static_cast<uint32_t>(60000 - std::max(entry, group)), static_cast<uint32_t>(entry),
                static_cast<uint32_t>(group)};
}

/// Per active pixel of ctx.light: the occluded fraction per channel from the groups' hard counts
/// and the binned wedges.
Image<DVec3> blend_pass(Backend& backend, const ShadowContext& ctx,
                        const WedgeBlendPass2Input& in) {
  VulkanContext& vk = backend.context();
  const GBuffer& g = ctx.gbuffer;
  const wedge_pass::BinnedWedges& bw = in.wedges;
  const wedge_pass::GroupCounts& gc = in.counts;
  const std::vector<WedgePixelGpu> pixels = wedge_pixels(ctx, ctx.light, bw.tiles_x);
  const uint32_t na = static_cast<uint32_t>(pixels.size());
  Image<DVec3> occ(g.width, g.height, DVec3(0.0));
  if (na == 0) return occ;
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
  // A pixel's walk costs at most two group steps per count entry and per bin entry, plus two
  // entry steps per bin entry.
  const Budget budget = budget_of(vk, in.emission);
  uint64_t most_cost = 0;
  for (uint32_t a = 0; a < na; ++a) {
    const uint32_t pixel = pixels[a].pixel, tile = pixels[a].tile;
    const uint64_t counts = gc.begin[pixel + 1] - gc.begin[pixel];
    const uint64_t entries = bins.begin[tile + 1] - bins.begin[tile];
    most_cost = std::max(
        most_cost, 2 * (counts + entries) * budget.group_cost + 2 * entries * budget.entry_cost);
  }
  // Every dispatch but the last spends at least `budget` of every unfinished pixel's cost; the
  // first starts the walk (the shader sets the state up), all but the last keep its state.
  const uint32_t dispatches =
      budget.entry_cost == 0 ? 1u : static_cast<uint32_t>(most_cost / budget.budget) + 2u;
  std::vector<DVec3> parts(in.parts.begin(), in.parts.end());
  std::vector<DVec3> density{DVec3(0.0)};
  int32_t em_w = 1, em_h = 1;
  if (in.emission) {
    density = in.emission->density;
    em_w = in.emission->width, em_h = in.emission->height;
  }
  const Buffer pix_buf = vk.upload(pixels);
  const Buffer wedge_buf = vk.upload(nonempty(wedges));
  const Buffer weight_buf = vk.upload(nonempty(weight));
  const Buffer group_buf = vk.upload(nonempty(bw.group));
  const Buffer begin_buf = vk.upload(bins.begin);
  const Buffer entry_buf = vk.upload(nonempty(bins.entries));
  const Buffer run_end_buf = vk.upload(nonempty(run_ends(bins, bw.group)));
  const Buffer count_begin = vk.upload(gc.begin);
  const Buffer count_group = vk.upload(nonempty(gc.group));
  const Buffer count_value = vk.upload(nonempty(gc.value));
  const Buffer state_buf(vk, (dispatches > 1 ? na : 1u) * sizeof(BlendState), Memory::device);
  const Buffer occ_buf(vk, static_cast<size_t>(na) * sizeof(DVec3), Memory::device);
  const Buffer part_buf = vk.upload(parts);
  const Buffer density_buf = vk.upload(density);
  const Shader shader =
      in.emission ? Shader::wedge_blend_pass2_textured : Shader::wedge_blend_pass2;
  const uint32_t costs = budget.entry_cost | budget.group_cost << 16;
  const uint32_t em_size = static_cast<uint32_t>(em_w) | static_cast<uint32_t>(em_h) << 16;
  CommandList cl(vk);
  for (uint32_t d = 0; d < dispatches; ++d) {
    cl.dispatch(
        backend.programs().get(shader),
        BlendPush{pix_buf.address(), wedge_buf.address(), weight_buf.address(), group_buf.address(),
                  begin_buf.address(), entry_buf.address(), run_end_buf.address(),
                  count_begin.address(), count_group.address(), count_value.address(),
                  state_buf.address(), occ_buf.address(), part_buf.address(), density_buf.address(),
                  na, budget.budget,
                  costs | (d == 0 ? kFirst : 0u) | (d + 1 < dispatches ? kStore : 0u), em_size},
        na);
    cl.barrier();
  }
  cl.mark("pass2_blend");
  cl.submit();
  const std::vector<DVec3> v = vk.download<DVec3>(occ_buf, na);
  for (uint32_t a = 0; a < na; ++a) occ[pixels[a].pixel] = v[a];
  return occ;
}

/// The CPU's `wedge_blend` (same stages and counters) with the per-pixel blend on the device.
class WedgeBlendVk final : public ShadowMethod {
 public:
  WedgeBlendVk(Backend& backend, const MethodOptions& o)
      : backend_(backend),
        method_(
            make_wedge_blend(o, [this](const ShadowContext& ctx, const WedgeBlendPass2Input& in) {
              return blend_pass(backend_, ctx, in);
            })) {}

  void prepare(const Scene& scene) override { method_->prepare(scene); }

  Visibility compute(const ShadowContext& ctx) override {
    if (!backend_.context().has_float64())
      throw Error("wedge_blend on vulkan needs shaderFloat64, which " +
                  backend_.context().device_name() + " lacks");
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
