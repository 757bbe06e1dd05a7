#version 460
// Exclusive prefix sum, second level: element i gets the scanned total of the blocks before its
// block of 1024.
#include "common.glsl"

layout(push_constant) uniform Push {
  Uints dst;
  Uints sums;
  uint n;
} pc;

void main() {
  const uint i = global_id();
  if (i < pc.n) pc.dst.v[i] += pc.sums.v[i / 1024u];
}
