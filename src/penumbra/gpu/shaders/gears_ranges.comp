#version 460
// GEARS step 3.3, after the sort by cell: each cell's [begin, end) in the sorted pairs (cells
// without pairs keep the zero fill).
#include "common.glsl"

layout(push_constant) uniform Push {
  Uints keys;  // sorted
  Uints begin;
  Uints end;
  uint n;
} pc;

void main() {
  const uint i = global_id();
  if (i >= pc.n) return;
  const uint key = pc.keys.v[i];
  if (i == 0u || pc.keys.v[i - 1u] != key) pc.begin.v[key] = i;
  if (i + 1u == pc.n || pc.keys.v[i + 1u] != key) pc.end.v[key] = i + 1u;
}
