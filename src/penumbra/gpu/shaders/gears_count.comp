#version 460
// GEARS step 3.3 [Wang 2014 §3.1, §4.2], count pass: the cells a triangle's shadow volume covers on
// the grid. The volume (the triangle extruded away from every light point to the deepest sample)
// is the convex hull of the vertices and their extrusions from the light corners, because central
// projection maps convex sets to convex sets; its projection through C is inside the 2D box of
// those points' projections. Conservative: the per-pixel rasterization decides every sample.
#include "common.glsl"
#include "gears.glsl"

layout(push_constant) uniform Push {
  GridCamera cam;
  Vec4s tris;  // 3 per triangle, light space
  Uints counts;
  Uints rects;  // x0, y0, x1, y1 per triangle (x1 < x0: none)
  Uints overflow;  // Σ counts / 1024, to detect a pair count beyond 32 bits
  Uints cell_max_z;
  Floats zmin;  // per triangle, for the write pass's identical test
  uint n;
} pc;

void main() {
  const uint t = global_id();
  if (t >= pc.n) return;
  GridCamera cam = pc.cam;
  vec3 v[3];
  for (int i = 0; i < 3; ++i) {
    v[i] = pc.tris.v[3u * t + uint(i)].xyz;
    v[i].z *= cam.side;
  }
  const float zmin = min(v[0].z, min(v[1].z, v[2].z));
  const float zmax = max(v[0].z, max(v[1].z, v[2].z));
  uvec4 rect = uvec4(1u, 0u, 0u, 0u);
  // Behind the whole light, or beyond every sample: blocks nothing on this side.
  if (!(zmax < cam.light_min_z) && !(zmin > cam.far_z)) {
    vec2 lo = vec2(1e30), hi = vec2(-1e30);
    // A vertex not strictly beyond every light point cannot be extruded: the whole grid.
    bool whole = !(zmin > cam.light_max_z);
    for (int i = 0; i < 3 && !whole; ++i) {
      const vec2 g = project_cells(cam, v[i]);
      lo = min(lo, g), hi = max(hi, g);
      for (int c = 0; c < cam.corner_count; ++c) {
        const vec3 l = cam.corners[c].xyz;
        const vec3 f = l + (v[i] - l) * ((cam.far_z - l.z) / (v[i].z - l.z));
        const vec2 h = project_cells(cam, f);
        lo = min(lo, h), hi = max(hi, h);
      }
    }
    if (any(isnan(lo)) || any(isnan(hi)) || any(isinf(lo)) || any(isinf(hi))) whole = true;
    const float res_x = float(cam.res_x), res_y = float(cam.res_y);
    if (whole) {
      rect = uvec4(0u, 0u, uint(cam.res_x - 1), uint(cam.res_y - 1));
    } else if (hi.x >= -1e-3 && hi.y >= -1e-3 && lo.x < res_x + 1e-3 && lo.y < res_y + 1e-3) {
      // A thousandth of a cell of slack covers the rounding of the samples' own projection.
      rect = uvec4(clamp(floor(lo - 1e-3), vec2(0.0), vec2(res_x - 1.0, res_y - 1.0)),
                   clamp(floor(hi + 1e-3), vec2(0.0), vec2(res_x - 1.0, res_y - 1.0)));
    }
  }
  // The cells of the box that have a sample the triangle may block.
  const bool beyond_light = zmin > cam.light_max_z;
  // One flat loop over the box (llvmpipe caps a loop at 65535 iterations, nested ones counted
  // together: grids up to 255² on lavapipe).
  uint count = 0u;
  const uint w = rect.z >= rect.x ? rect.z - rect.x + 1u : 0u;
  const uint area = rect.w >= rect.y ? w * (rect.w - rect.y + 1u) : 0u;
  for (uint i = 0u; i < area; ++i) {
    const uint c = (rect.y + i / w) * uint(cam.res_x) + rect.x + i % w;
    count += cell_may_be_blocked(pc.cell_max_z, c, zmin, beyond_light) ? 1u : 0u;
  }
  pc.counts.v[t] = count;
  pc.rects.v[4u * t] = rect.x;
  pc.rects.v[4u * t + 1u] = rect.y;
  pc.rects.v[4u * t + 2u] = rect.z;
  pc.rects.v[4u * t + 3u] = rect.w;
  pc.zmin.v[t] = zmin;
  if (count >= 1024u) atomicAdd(pc.overflow.v[0], count >> 10u);
}
