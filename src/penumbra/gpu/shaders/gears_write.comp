#version 460
// GEARS step 3.3, write pass: triangle t writes its (cell, t) pairs from its scanned offset (the
// count pass's cells, by the same test).
#include "common.glsl"
#include "gears.glsl"

layout(push_constant) uniform Push {
  Uints rects;
  Uints offsets;  // exclusive prefix sum of the counts
  Uints keys;     // cell
  Uints vals;     // triangle
  Uints cell_max_z;
  Floats zmin;
  uint n;
  uint res_x;
  float light_max_z;
} pc;

void main() {
  const uint t = global_id();
  if (t >= pc.n) return;
  const uvec4 r = uvec4(pc.rects.v[4u * t], pc.rects.v[4u * t + 1u], pc.rects.v[4u * t + 2u],
                        pc.rects.v[4u * t + 3u]);
  if (r.z < r.x || r.w < r.y) return;
  uint o = pc.offsets.v[t];
  const float zmin = pc.zmin.v[t];
  const bool beyond_light = zmin > pc.light_max_z;
  const uint w = r.z - r.x + 1u, area = w * (r.w - r.y + 1u);
  for (uint i = 0u; i < area; ++i) {
    const uint c = (r.y + i / w) * pc.res_x + r.x + i % w;
    if (!cell_may_be_blocked(pc.cell_max_z, c, zmin, beyond_light)) continue;
    pc.keys.v[o] = c;
    pc.vals.v[o] = t;
    ++o;
  }
}
