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
  VkDeviceAddress pix, wedges, weight, wedge_group, bin_begin, bin_entries, count_begin,
      count_group, count_value, state, occ, part, density;
  uint32_t na, budget, entry_cost, group_cost;
  int32_t em_w, em_h;
};
static_assert(sizeof(BlendPush) <= kPushBytes);

/// wedge_blend_pass2.glsl State: the V-buffer (per part the occlusion per channel and the
/// rectangle), the next count entry and the next bin entry.
struct BlendState {
  double v_occ[4][3];
  double v_rect[4][4];
  uint32_t ci, bi;
};
static_assert(sizeof(BlendState) == 232);

/// The longest run of one group's wedges in a bin: what one invocation must walk at once.
uint32_t longest_group_run(const wedge_pass::BinnedWedges& bw) {
  uint32_t longest = 0;
  for (const std::vector<uint32_t>& bin : bw.bins)
    for (size_t j = 0, k = 0; j < bin.size(); j = k) {
      k = j + 1;
      while (k < bin.size() && bw.group[bin[k]] == bw.group[bin[j]]) ++k;
      longest = std::max(longest, static_cast<uint32_t>(k - j));
    }
  return longest;
}

/// How many loop iterations a dispatch may spend per pixel. llvmpipe stops an invocation after
/// 65535 loop iterations in all: a bin entry costs up to ~250 (both passes' wedge test and clips,
/// the sectors of the parts it reaches), a group's blend ~50; a textured light adds ~300 per texel
/// to an entry (its parts' weighted sectors, wedge_emission.glsl weigh_polygon) and ~720 to a
/// group (three rectangles per blended part). Whole groups are walked, so the longest run of one
/// group in a bin must fit alone. Other devices walk every pixel's bin at once.
struct Budget {
  uint32_t budget = 0xffffffffu, entry_cost = 0, group_cost = 0;
};
Budget budget_of(const VulkanContext& vk, const LightEmission* emission,
                 const wedge_pass::BinnedWedges& bw) {
  if (vk.info().type != "cpu") return {};
  const uint32_t texels = emission ? static_cast<uint32_t>(emission->width * emission->height) : 0u;
  Budget b{0, 250 + 300 * texels, 50 + 720 * texels};
  const uint32_t run = longest_group_run(bw);
  const uint64_t group = static_cast<uint64_t>(run) * b.entry_cost + b.group_cost;
  if (group + b.group_cost + b.entry_cost > 60000)
    throw Error("wedge_blend on vulkan: a caster group with " + std::to_string(run) +
                " wedges in one 16x16 tile" +
                (emission ? " under a " + std::to_string(emission->width) + "x" +
                                std::to_string(emission->height) + " light texture"
                          : std::string()) +
                " exceeds lavapipe's loop limit (use --backend cpu)");
  b.budget = static_cast<uint32_t>(60000 - group);
  return b;
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
  // The walk's start: an empty V-buffer, each pixel's first count entry and its tile's first
  // wedge. A pixel's walk costs at most a group per count entry and per bin entry, plus the
  // entries.
  const Budget budget = budget_of(vk, in.emission, bw);
  const double inf = kInfinity;
  std::vector<BlendState> state(na);
  uint64_t most_cost = 0;
  for (uint32_t a = 0; a < na; ++a) {
    BlendState& s = state[a];
    s = {};
    for (auto& r : s.v_rect) r[0] = inf, r[1] = inf, r[2] = -inf, r[3] = -inf;
    const uint32_t pixel = pixels[a].pixel, tile = pixels[a].tile;
    s.ci = gc.begin[pixel];
    s.bi = bins.begin[tile];
    const uint32_t counts = gc.begin[pixel + 1] - gc.begin[pixel];
    const uint64_t entries = bins.begin[tile + 1] - bins.begin[tile];
    most_cost =
        std::max(most_cost, (counts + entries) * budget.group_cost + entries * budget.entry_cost);
  }
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
  const Buffer count_begin = vk.upload(gc.begin);
  const Buffer count_group = vk.upload(nonempty(gc.group));
  const Buffer count_value = vk.upload(nonempty(gc.value));
  const Buffer state_buf = vk.upload(state);
  const Buffer occ_buf(vk, static_cast<size_t>(na) * sizeof(DVec3), Memory::device);
  const Buffer part_buf = vk.upload(parts);
  const Buffer density_buf = vk.upload(density);
  const Shader shader =
      in.emission ? Shader::wedge_blend_pass2_textured : Shader::wedge_blend_pass2;
  // Every dispatch but the last spends at least `budget` of every unfinished pixel's cost.
  const uint32_t dispatches =
      budget.entry_cost == 0 ? 1u : static_cast<uint32_t>(most_cost / budget.budget) + 1u;
  CommandList cl(vk);
  for (uint32_t d = 0; d < dispatches; ++d) {
    cl.dispatch(
        backend.programs().get(shader),
        BlendPush{pix_buf.address(), wedge_buf.address(), weight_buf.address(), group_buf.address(),
                  begin_buf.address(), entry_buf.address(), count_begin.address(),
                  count_group.address(), count_value.address(), state_buf.address(),
                  occ_buf.address(), part_buf.address(), density_buf.address(), na, budget.budget,
                  budget.entry_cost, budget.group_cost, em_w, em_h},
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
