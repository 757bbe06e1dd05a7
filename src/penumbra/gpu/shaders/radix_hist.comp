#version 460
// LSD radix sort, one 8-bit digit: per-block digit counts. Block b (256 × keys_per_thread keys:
// the scatter shader's block) writes the count of digit d to hist[d·blocks + b], so an exclusive
// scan of hist gives every (digit, block) its first output slot — digit-major, block order within
// a digit: stable.
#include "common.glsl"

layout(push_constant) uniform Push {
  Uints keys;
  Uints hist;
  uint n;
  uint shift;
  uint blocks;
  uint keys_per_thread;
} pc;

shared uint count[256];

void main() {
  const uint lid = gl_LocalInvocationIndex;
  count[lid] = 0u;
  barrier();
  for (uint k = 0u; k < pc.keys_per_thread; ++k) {
    const uint i = (group_id() * pc.keys_per_thread + k) * 256u + lid;
    if (i < pc.n) atomicAdd(count[(pc.keys.v[i] >> pc.shift) & 255u], 1u);
  }
  barrier();
  pc.hist.v[lid * pc.blocks + group_id()] = count[lid];
}
