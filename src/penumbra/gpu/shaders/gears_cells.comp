#version 460
// GEARS step 3.2 [Wang 2014 §3.1]: each active pixel's sample → its grid cell (~0: the sample is on
// the other side of the light plane, computed by the other pass), and each cell's deepest sample.
// Also the pixel's depth cut (pix's first w): a triangle nearer than it may block the sample, no
// other (a blocker on the segment to light point X lies no deeper than max(sample z, X.z)), as the
// CPU's per-pixel cut.
#include "common.glsl"
#include "gears.glsl"

layout(push_constant) uniform Push {
  GridCamera cam;
  Vec4s pix;  // per active pixel: p, w, eu, ev, slab bounds (light space); p.w: the depth cut
  Uints cell;
  Uints cell_max_z;  // per cell: bits of the deepest sample's z, + 1 (0: no sample); zero-filled
  uint n;
} pc;

void main() {
  const uint a = global_id();
  if (a >= pc.n) return;
  const vec3 p = pc.pix.v[5u * a].xyz;
  if ((pc.cam.side > 0.0) != (p.z >= 0.0)) {
    pc.cell.v[a] = 0xffffffffu;
    return;
  }
  const float z = pc.cam.side * p.z;
  pc.pix.v[5u * a].w = max(z, pc.cam.light_max_z);
  const vec2 c = project_cells(pc.cam, vec3(p.xy, z));
  // Clamped in float first (a sample on the eye plane projects to infinity); NaN → cell 0.
  const float fx = isnan(c.x) ? 0.0 : clamp(floor(c.x), 0.0, float(pc.cam.res_x - 1));
  const float fy = isnan(c.y) ? 0.0 : clamp(floor(c.y), 0.0, float(pc.cam.res_y - 1));
  const uint cell = uint(fy) * uint(pc.cam.res_x) + uint(fx);
  pc.cell.v[a] = cell;
  // z ≥ 0 on this side: non-negative floats order like their bits.
  atomicMax(pc.cell_max_z.v[cell], (z > 0.0 ? floatBitsToUint(z) : 0u) + 1u);
}
