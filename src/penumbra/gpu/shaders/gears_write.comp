#version 460
// GEARS step 3.3, write pass: triangle t writes its (cell, t) pairs from its scanned offset.
#include "common.glsl"

layout(push_constant) uniform Push {
  Uints rects;
  Uints offsets;  // exclusive prefix sum of the counts
  Uints keys;     // cell
  Uints vals;     // triangle
  uint n;
  uint res_x;
} pc;

void main() {
  const uint t = global_id();
  if (t >= pc.n) return;
  const uvec4 r = uvec4(pc.rects.v[4u * t], pc.rects.v[4u * t + 1u], pc.rects.v[4u * t + 2u],
                        pc.rects.v[4u * t + 3u]);
  if (r.z < r.x || r.w < r.y) return;
  uint o = pc.offsets.v[t];
  for (uint y = r.y; y <= r.w; ++y)
    for (uint x = r.x; x <= r.z; ++x) {
      pc.keys.v[o] = y * pc.res_x + x;
      pc.vals.v[o] = t;
      ++o;
    }
}
