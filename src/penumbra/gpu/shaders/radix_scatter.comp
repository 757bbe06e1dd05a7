#version 460
// LSD radix sort, one 8-bit digit: stable scatter with linear ranking [Wang 2014 §4.2: the
// triangle–cell pairs sorted by cell]. A block of 1024 keys (kKeysPerThread per thread) gives
// subgroup s the contiguous chunk [s, s + 1) × kKeysPerThread × subgroup size, read in rounds of
// one key per lane. A key's slot = the scanned count of its (digit, block) + its rank among the
// block's keys with the same digit:
//   1. within its round: eight ballots (one per digit bit) leave the mask of the lanes holding the
//      same digit; the rank is the number of those before this lane;
//   2. within its subgroup: the running count of its digit over the earlier rounds (shared, one
//      16-bit counter per subgroup and digit, added to by the digit's first lane each round);
//   3. across subgroups: those counts exclusive-scanned over the subgroups, one thread per pair
//      of digits.
// Work per block: 8 ballots per key + (subgroups × 256) counts for 1024 keys, against the
// 256²/8 byte compares per 256 keys of radix_scatter_compare.comp. The ranks follow the order
// (subgroup, round, lane) in which the keys are read: stable by construction.
#extension GL_KHR_shader_subgroup_basic : require
#extension GL_KHR_shader_subgroup_ballot : require
#include "common.glsl"

layout(push_constant) uniform Push {
  Uints keys_in;
  Uints vals_in;
  Uints keys_out;
  Uints vals_out;
  Uints hist;  // scanned
  uint n;
  uint shift;
  uint blocks;
} pc;

const uint kKeysPerThread = 4u;  // sort.cpp: kBallotKeysPerThread
// Subgroups of at least 8 invocations (VulkanContext::has_subgroup_ballot): at most 32 per block.
// Count of digit d in subgroup s: 16 bits (d & 1) of word s·128 + d / 2 (≤ 1024: fits). A word is
// only touched by its own subgroup during the rounds and by one thread during the scan. 16 KiB.
const uint kMaxSubgroups = 32u;
shared uint counts[kMaxSubgroups * 128u];

uint bit_count4(uvec4 m) {
  return bitCount(m.x) + bitCount(m.y) + bitCount(m.z) + bitCount(m.w);
}

void main() {
  const uint lid = gl_LocalInvocationIndex;
  const uint s = gl_SubgroupID, sg = gl_SubgroupSize;
  const uint block_first = group_id() * 256u * kKeysPerThread;
  const uint chunk = s * kKeysPerThread * sg + gl_SubgroupInvocationID;
  for (uint w = lid; w < gl_NumSubgroups * 128u; w += 256u) counts[w] = 0u;
  barrier();

  uint digit[kKeysPerThread], rank[kKeysPerThread];
  for (uint r = 0u; r < kKeysPerThread; ++r) {
    const uint i = block_first + chunk + r * sg;
    const bool live = i < pc.n;
    const uint d = live ? (pc.keys_in.v[i] >> pc.shift) & 255u : 0u;
    uvec4 same = subgroupBallot(live);
    for (uint b = 0u; b < 8u; ++b) {
      const bool set = ((d >> b) & 1u) != 0u;
      const uvec4 ones = subgroupBallot(set);
      same &= set ? ones : ~ones;
    }
    const uint in_round = bit_count4(same & gl_SubgroupLtMask);
    const uint word = s * 128u + (d >> 1u), half_shift = 16u * (d & 1u);
    const uint earlier = (counts[word] >> half_shift) & 0xffffu;  // this digit, earlier rounds
    subgroupBarrier();  // every lane has read before the first lanes add
    if (live && in_round == 0u) atomicAdd(counts[word], bit_count4(same) << half_shift);
    subgroupBarrier();  // the next round reads the sums
    digit[r] = d;
    rank[r] = earlier + in_round;
  }
  barrier();

  // Thread lid < 128 scans digits 2·lid and 2·lid + 1 over the subgroups (exclusive; prefixes
  // ≤ 1024 fit).
  if (lid < 128u) {
    uint run_lo = 0u, run_hi = 0u;
    for (uint g = 0u; g < gl_NumSubgroups; ++g) {
      const uint c = counts[g * 128u + lid];
      counts[g * 128u + lid] = run_lo | (run_hi << 16u);
      run_lo += c & 0xffffu;
      run_hi += c >> 16u;
    }
  }
  barrier();
  for (uint r = 0u; r < kKeysPerThread; ++r) {
    const uint i = block_first + chunk + r * sg;
    if (i >= pc.n) continue;
    const uint d = digit[r];
    const uint before = (counts[s * 128u + (d >> 1u)] >> (16u * (d & 1u))) & 0xffffu;
    const uint slot = pc.hist.v[d * pc.blocks + group_id()] + before + rank[r];
    pc.keys_out.v[slot] = pc.keys_in.v[i];
    pc.vals_out.v[slot] = pc.vals_in.v[i];
  }
}
