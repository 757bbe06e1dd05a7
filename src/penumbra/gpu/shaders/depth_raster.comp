#version 460
// The exact depth pass without the graphics pipeline (devices with few graphics units): one
// workgroup per caster triangle, its threads striding over the pixel box depth_setup.comp found,
// each texel centre tested by rasterize_triangle's edge functions and 1/w interpolation
// (depth_exact.glsl nearest_depth, as depth_map_exact.frag) and the nearest depth kept by an
// integer atomicMin: positive floats order like their bit patterns. Same map as the raster path.
#include "common.glsl"
#include "depth_exact.glsl"

layout(push_constant) uniform Push {
  ScreenPolys polys;
  Uints depth;  // resolution² float bits, row 0 at the top; filled with kEmptyDepth's before
  uint triangles;
  int resolution;
} pc;

void main() {
  const uint t = global_id() / 256u;
  if (t >= pc.triangles || pc.polys.p[t].count == 0) return;
  const int x0 = pc.polys.p[t].x0, y0 = pc.polys.p[t].y0;
  const uint w = uint(pc.polys.p[t].x1 - x0 + 1), h = uint(pc.polys.p[t].y1 - y0 + 1);
  for (uint k = gl_LocalInvocationIndex; k < w * h; k += 256u) {
    const int x = x0 + int(k % w), y = y0 + int(k / w);
    float depth;
    if (nearest_depth(pc.polys, t, double(x) + 0.5, double(y) + 0.5, depth))
      atomicMin(pc.depth.v[uint(y * pc.resolution + x)], floatBitsToUint(depth));
  }
}
