#version 460
// LSD radix sort, one 8-bit digit: stable scatter with linear ranking [Wang 2014 §4.2: the
// triangle–cell pairs sorted by cell]. A key's slot = the scanned count of its (digit, block) +
// its rank among the block's keys with the same digit:
//   1. within its subgroup: eight ballots (one per digit bit) leave the mask of the lanes holding
//      the same digit; the rank is the number of those before this lane;
//   2. across subgroups: each digit's count per subgroup, exclusive-scanned over the subgroups by
//      the thread of that digit (256 threads, 256 digits).
// Work per block: 8 ballots per key + (subgroups × 256) counts, against the 256²/8 byte compares
// of radix_scatter_compare.comp. A key's position in the block is (subgroup, lane), so the order
// the ranks follow is the order the keys are read in: stable by construction.
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

// Subgroups of at least 8 invocations (VulkanContext::has_subgroup_ballot): at most 32 per block.
// Count of digit d in subgroup s: 16 bits (s & 1) of word (s / 2)·256 + d, so the thread of
// digit d owns every word of its column during the scan. 16 KiB.
const uint kMaxSubgroups = 32u;
shared uint counts[(kMaxSubgroups / 2u) * 256u];

uint bit_count4(uvec4 m) {
  return bitCount(m.x) + bitCount(m.y) + bitCount(m.z) + bitCount(m.w);
}

void main() {
  const uint lid = gl_LocalInvocationIndex;
  const uint s = gl_SubgroupID;
  const uint position = s * gl_SubgroupSize + gl_SubgroupInvocationID;  // in the block
  const uint i = group_id() * 256u + position;
  const bool live = i < pc.n;
  uint key = 0u, d = 0u;
  if (live) {
    key = pc.keys_in.v[i];
    d = (key >> pc.shift) & 255u;
  }
  const uint words = ((gl_NumSubgroups + 1u) / 2u) * 256u;
  for (uint w = lid; w < words; w += 256u) counts[w] = 0u;
  barrier();

  uvec4 same = subgroupBallot(live);
  for (uint b = 0u; b < 8u; ++b) {
    const bool set = ((d >> b) & 1u) != 0u;
    const uvec4 ones = subgroupBallot(set);
    same &= set ? ones : ~ones;
  }
  const uint rank_in_subgroup = bit_count4(same & gl_SubgroupLtMask);
  const uint word = (s >> 1u) * 256u + d, half_shift = 16u * (s & 1u);
  // The first lane of each digit adds the subgroup's count (two subgroups share a word).
  if (live && rank_in_subgroup == 0u) atomicAdd(counts[word], bit_count4(same) << half_shift);
  barrier();

  // Thread lid scans digit lid's counts over the subgroups (exclusive; prefixes ≤ 256 fit 16 bits).
  uint run = 0u;
  for (uint w = lid; w < words; w += 256u) {
    const uint c = counts[w];
    const uint lo = c & 0xffffu, hi = c >> 16u;
    counts[w] = run | ((run + lo) << 16u);
    run += lo + hi;
  }
  barrier();
  if (!live) return;
  const uint before = (counts[word] >> half_shift) & 0xffffu;
  const uint slot = pc.hist.v[d * pc.blocks + group_id()] + before + rank_in_subgroup;
  pc.keys_out.v[slot] = key;
  pc.vals_out.v[slot] = pc.vals_in.v[i];
}
