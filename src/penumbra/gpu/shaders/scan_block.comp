#version 460
// Exclusive prefix sum, first level: each workgroup scans 1024 elements (4 per thread) and writes
// its total to sums[group]; scan_add.comp then adds the scanned totals (gpu/prefix_sum.cpp).
#include "common.glsl"

layout(push_constant) uniform Push {
  Uints src;
  Uints dst;
  Uints sums;
  uint n;
} pc;

shared uint part[256];

void main() {
  const uint lid = gl_LocalInvocationIndex;
  const uint base = group_id() * 1024u + lid * 4u;
  uint v[4];
  uint sum = 0u;
  for (uint i = 0u; i < 4u; ++i) {
    v[i] = base + i < pc.n ? pc.src.v[base + i] : 0u;
    sum += v[i];
  }
  part[lid] = sum;
  barrier();
  for (uint off = 1u; off < 256u; off <<= 1u) {
    const uint t = lid >= off ? part[lid - off] : 0u;
    barrier();
    part[lid] += t;
    barrier();
  }
  uint run = part[lid] - sum;
  for (uint i = 0u; i < 4u; ++i) {
    if (base + i < pc.n) pc.dst.v[base + i] = run;
    run += v[i];
  }
  if (lid == 255u) pc.sums.v[group_id()] = part[255];
}
