#include "penumbra/gpu/sort.hpp"

#include "penumbra/core/error.hpp"

namespace penumbra::gpu {

namespace {

struct ScanBlockPush {
  VkDeviceAddress src, dst, sums;
  uint32_t n;
};
struct ScanAddPush {
  VkDeviceAddress dst, sums;
  uint32_t n;
};
struct HistPush {
  VkDeviceAddress keys, hist;
  uint32_t n, shift, blocks, keys_per_thread;
};
struct ScatterPush {
  VkDeviceAddress keys_in, vals_in, keys_out, vals_out, hist;
  uint32_t n, shift, blocks;
};

constexpr uint32_t kScanBlock = 1024;         // elements per workgroup of scan_block.comp
constexpr uint32_t kBallotKeysPerThread = 4;  // radix_scatter.comp's kKeysPerThread

}  // namespace

void record_exclusive_scan(Programs& programs, CommandList& cl, const Buffer& data, uint32_t n,
                           std::deque<Buffer>& scratch) {
  if (n == 0) return;
  const uint32_t blocks = (n + kScanBlock - 1) / kScanBlock;
  scratch.emplace_back(programs.context(), size_t{blocks} * 4, Memory::device);
  const Buffer& sums = scratch.back();
  cl.dispatch_groups(programs.get(Shader::scan_block),
                     ScanBlockPush{data.address(), data.address(), sums.address(), n}, blocks);
  cl.barrier();
  if (blocks == 1) return;  // the single block's prefix is already global
  record_exclusive_scan(programs, cl, sums, blocks, scratch);
  cl.dispatch(programs.get(Shader::scan_add), ScanAddPush{data.address(), sums.address(), n}, n);
  cl.barrier();
}

bool record_radix_sort(Programs& programs, CommandList& cl, const Buffer& keys,
                       const Buffer& values, const Buffer& keys_tmp, const Buffer& vals_tmp,
                       uint32_t n, int key_bits, std::deque<Buffer>& scratch,
                       RadixRanking ranking) {
  if (n == 0) return true;
  const VulkanContext& vk = programs.context();
  const bool ballot = ranking == RadixRanking::ballot ||
                      (ranking == RadixRanking::best && vk.has_subgroup_ballot());
  if (ballot && !vk.has_subgroup_ballot())
    throw Error("vulkan: the device has no subgroup ballots for the radix sort");
  const ComputePipeline& scatter =
      programs.get(ballot ? Shader::radix_scatter : Shader::radix_scatter_compare);
  // radix_scatter.comp ranks kBallotKeysPerThread keys per thread (blocks of 1024 keys).
  const uint32_t per_thread = ballot ? kBallotKeysPerThread : 1;
  const uint32_t block_keys = kGroupSize * per_thread;
  const uint32_t blocks = (n + block_keys - 1) / block_keys;
  scratch.emplace_back(programs.context(), size_t{blocks} * 256 * 4, Memory::device);
  const Buffer& hist = scratch.back();
  const Buffer* src_k = &keys;
  const Buffer* src_v = &values;
  const Buffer* dst_k = &keys_tmp;
  const Buffer* dst_v = &vals_tmp;
  for (int shift = 0; shift < key_bits; shift += 8) {
    const uint32_t s = static_cast<uint32_t>(shift);
    cl.dispatch(programs.get(Shader::radix_hist),
                HistPush{src_k->address(), hist.address(), n, s, blocks, per_thread},
                size_t{blocks} * kGroupSize);
    cl.barrier();
    record_exclusive_scan(programs, cl, hist, blocks * 256, scratch);
    cl.dispatch(scatter,
                ScatterPush{src_k->address(), src_v->address(), dst_k->address(), dst_v->address(),
                            hist.address(), n, s, blocks},
                size_t{blocks} * kGroupSize);
    cl.barrier();
    std::swap(src_k, dst_k);
    std::swap(src_v, dst_v);
  }
  return src_k == &keys;
}

}  // namespace penumbra::gpu
