#version 460
// The nearest depth stored anywhere in the map (PCSS's blocker-search bound): positive floats
// order like their bit patterns, so an integer atomicMin reduces them. Each thread first reduces
// kTexelsPerThread texels (strided by the group size: neighbouring threads read neighbouring
// texels), so a 2048² map takes 256 groups, not 16384: barriers and the one atomic per group are
// what cost (on lavapipe the per-texel version took ~0.5 s).
#include "common.glsl"

layout(push_constant) uniform Push {
  Floats depth;
  Uints result;  // float bits; filled with FLT_MAX's before
  uint n;
} pc;

const uint kTexelsPerThread = 64u;  // DepthMapVk: dispatches n / kTexelsPerThread threads

shared uint best[256];

void main() {
  const uint lid = gl_LocalInvocationIndex;
  const uint first = group_id() * 256u * kTexelsPerThread + lid;
  uint m = 0x7f7fffffu;
  for (uint k = 0u; k < kTexelsPerThread; ++k) {
    const uint i = first + k * 256u;
    if (i < pc.n) m = min(m, floatBitsToUint(max(pc.depth.v[i], 0.0)));
  }
  best[lid] = m;
  barrier();
  for (uint s = 128u; s > 0u; s >>= 1u) {
    if (lid < s) best[lid] = min(best[lid], best[lid + s]);
    barrier();
  }
  if (lid == 0u) atomicMin(pc.result.v[0], best[0]);
}
