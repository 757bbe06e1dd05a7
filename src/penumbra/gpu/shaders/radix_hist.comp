#version 460
// LSD radix sort, one 8-bit digit: per-block digit counts. Block b (256 keys, one per thread)
// writes the count of digit d to hist[d·blocks + b], so an exclusive scan of hist gives every
// (digit, block) its first output slot — digit-major, block order within a digit: stable.
#include "common.glsl"

layout(push_constant) uniform Push {
  Uints keys;
  Uints hist;
  uint n;
  uint shift;
  uint blocks;
} pc;

shared uint count[256];

void main() {
  const uint lid = gl_LocalInvocationIndex;
  count[lid] = 0u;
  barrier();
  const uint i = global_id();
  if (i < pc.n) atomicAdd(count[(pc.keys.v[i] >> pc.shift) & 255u], 1u);
  barrier();
  pc.hist.v[lid * pc.blocks + group_id()] = count[lid];
}
