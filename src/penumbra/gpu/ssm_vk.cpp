// `ssm` on Vulkan: soft shadow maps [Atty 2006 §3] with the blending of the micro-patches'
// occlusion into the soft shadow map — the method's cost, occluder texels × extent texels (§5.1) —
// in a compute shader (ssm_blend.comp); the occluder and receiver maps, the micro-patches and
// their extents, the two-pass merge and the projection onto the G-buffer are the CPU method's
// (depth_maps/ssm.hpp make_ssm). Per texel the GPU sums the same float terms in the same order,
// so the soft shadow maps, hence V, are the CPU's.
#include <algorithm>
#include <chrono>

#include "penumbra/core/error.hpp"
#include "penumbra/gpu/backend.hpp"
#include "penumbra/shadows/depth_maps/ssm.hpp"

namespace penumbra::gpu {

namespace {

struct PatchGpu {
  double px, py, hx, hy, zo;
  int32_t i0, i1, j0, j1;
};
static_assert(sizeof(PatchGpu) == 56);

struct BlendPush {
  VkDeviceAddress patches, bin_begin, bin_entries, rmap, acc, touched;
  double tx0, ty1, dx, dy, lu, lv;
  uint32_t w, h, tiles_x, first, chunk;
};
static_assert(sizeof(BlendPush) <= kPushBytes);

constexpr int kTile = 16;  // ssm_blend.comp's tiles

/// Patches per dispatch: llvmpipe stops an invocation after 65535 loop iterations; other devices
/// walk a whole bin at once.
uint32_t patch_chunk(const VulkanContext& vk) {
  return vk.info().type == "cpu" ? 60000u : UINT32_MAX / 2;
}

Image<float> blend(Backend& backend, const std::vector<ssm::Patch>& patches, const ssm::Window& sw,
                   const Image<float>& rmap, const ssm::LightRect& light, double& touched) {
  VulkanContext& vk = backend.context();
  const uint32_t w = static_cast<uint32_t>(sw.w), h = static_cast<uint32_t>(sw.h);
  const uint32_t tiles_x = (w + kTile - 1) / kTile, tiles_y = (h + kTile - 1) / kTile;
  // Each tile's patches in patch order (the blending order): a texel's sum is the CPU's.
  std::vector<std::vector<uint32_t>> bins(size_t{tiles_x} * tiles_y);
  std::vector<PatchGpu> gpu_patches;
  gpu_patches.reserve(patches.size());
  for (size_t k = 0; k < patches.size(); ++k) {
    const ssm::Patch& p = patches[k];
    gpu_patches.push_back({p.px, p.py, p.hx, p.hy, p.zo, p.i0, p.i1, p.j0, p.j1});
    for (int ty = p.j0 / kTile; ty <= p.j1 / kTile; ++ty)
      for (int tx = p.i0 / kTile; tx <= p.i1 / kTile; ++tx)
        bins[static_cast<size_t>(ty) * tiles_x + tx].push_back(static_cast<uint32_t>(k));
  }
  std::vector<uint32_t> begin{0}, entries;
  uint32_t longest = 0;
  for (const std::vector<uint32_t>& bin : bins) {
    entries.insert(entries.end(), bin.begin(), bin.end());
    begin.push_back(static_cast<uint32_t>(entries.size()));
    longest = std::max(longest, static_cast<uint32_t>(bin.size()));
  }
  const Buffer patch_buf = vk.upload(gpu_patches);
  const Buffer begin_buf = vk.upload(begin);
  const Buffer entry_buf = vk.upload(entries);
  const Buffer rmap_buf = vk.upload(rmap.pixels().data(), rmap.size() * sizeof(float));
  const Buffer acc(vk, std::max<size_t>(rmap.size(), 1) * 4, Memory::device);
  const Buffer touched_buf(vk, 4, Memory::device);
  CommandList cl(vk);
  cl.fill(acc, 0);
  cl.fill(touched_buf, 0);
  cl.barrier();
  const uint32_t chunk = patch_chunk(vk);
  for (uint32_t first = 0; first < longest; first += chunk) {
    cl.dispatch(backend.programs().get(Shader::ssm_blend),
                BlendPush{patch_buf.address(), begin_buf.address(), entry_buf.address(),
                          rmap_buf.address(), acc.address(), touched_buf.address(), sw.tx0, sw.ty1,
                          sw.dx(), sw.dy(), light.lu, light.lv, w, h, tiles_x, first, chunk},
                size_t{w} * h);
    cl.barrier();
  }
  cl.mark("blend");
  StageTimes times;
  cl.submit(&times);
  Image<float> out(sw.w, sw.h, 0.0f);
  vk.download(acc, out.pixels().data(), out.size() * sizeof(float));
  touched = vk.download<uint32_t>(touched_buf, 1)[0];
  return out;
}

}  // namespace

std::unique_ptr<ShadowMethod> create_ssm_vk(Backend& backend, const MethodOptions& options) {
  if (!backend.context().has_float64())
    throw Error("ssm on vulkan needs shaderFloat64, which " + backend.context().device_name() +
                " lacks");
  if (options.get_bool("fp16"))
    throw Error("ssm.fp16 has no Vulkan path (the binary16 blending emulation runs on the CPU)");
  return ssm::make_ssm(
      options, [&backend](const std::vector<ssm::Patch>& patches, const ssm::Window& sw,
                          const Image<float>& rmap, const ssm::LightRect& light, double& touched) {
        return blend(backend, patches, sw, rmap, light, touched);
      });
}

}  // namespace penumbra::gpu
