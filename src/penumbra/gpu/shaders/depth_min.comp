#version 460
// The nearest depth stored anywhere in the map (PCSS's blocker-search bound): positive floats
// order like their bit patterns, so an integer atomicMin reduces them.
#include "common.glsl"

layout(push_constant) uniform Push {
  Floats depth;
  Uints result;  // float bits; filled with FLT_MAX's before
  uint n;
} pc;

shared uint best[256];

void main() {
  const uint lid = gl_LocalInvocationIndex;
  const uint i = global_id();
  best[lid] = i < pc.n ? floatBitsToUint(max(pc.depth.v[i], 0.0)) : 0x7f7fffffu;
  barrier();
  for (uint s = 128u; s > 0u; s >>= 1u) {
    if (lid < s) best[lid] = min(best[lid], best[lid + s]);
    barrier();
  }
  if (lid == 0u) atomicMin(pc.result.v[0], best[0]);
}
