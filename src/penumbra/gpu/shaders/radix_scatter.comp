#version 460
// LSD radix sort, one 8-bit digit: stable scatter. A key's slot = the scanned count of its
// (digit, block) + the number of keys with the same digit before it in its block.
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

shared uint digit[256];

void main() {
  const uint lid = gl_LocalInvocationIndex;
  const uint i = global_id();
  const bool live = i < pc.n;
  uint key = 0u, d = 256u;  // 256: no digit (past the end)
  if (live) {
    key = pc.keys_in.v[i];
    d = (key >> pc.shift) & 255u;
  }
  digit[lid] = d;
  barrier();
  if (!live) return;
  uint rank = 0u;
  for (uint j = 0u; j < lid; ++j) rank += digit[j] == d ? 1u : 0u;
  const uint slot = pc.hist.v[d * pc.blocks + group_id()] + rank;
  pc.keys_out.v[slot] = key;
  pc.vals_out.v[slot] = pc.vals_in.v[i];
}
