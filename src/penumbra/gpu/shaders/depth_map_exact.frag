#version 460
// Exact depth pass (depth_exact.glsl): rasterize_triangle's coverage test and 1/w interpolation at
// this texel centre, over the fan pieces of the caster's clipped screen polygon, in double
// (`precise`). The nearest depth wins through the depth attachment: gl_FragDepth is the view depth
// times a power of two (exact, so the float order is the depth order), tested LESS.
#include "depth_exact.glsl"

layout(push_constant) uniform Push {
  ScreenPolys polys;
  float resolution;
  float depth_scale;  // 2^-k ≥ 1 / the farthest caster point
} pc;

layout(location = 0) flat in uint triangle;
layout(location = 0) out float stored_depth;

/// rasterize_triangle's edge test at (px, py) for screen triangle a0 b0 c0; inv_w at the centre.
bool covers(dvec3 a0, dvec3 b0, dvec3 c0, double px, double py, out double inv_w) {
  precise const double area = (b0.x - a0.x) * (c0.y - a0.y) - (b0.y - a0.y) * (c0.x - a0.x);
  inv_w = 0.0;
  if (!(area != 0.0) || isinf(area) || isnan(area)) return false;
  dvec3 v[3] = {a0, area > 0.0 ? b0 : c0, area > 0.0 ? c0 : b0};
  precise double w[3];
  for (int i = 0; i < 3; ++i) {
    const dvec3 p = v[(i + 1) % 3], q = v[(i + 2) % 3];
    const bool p_first = p.x < q.x || (p.x == q.x && p.y < q.y);
    const dvec3 base = p_first ? p : q, other = p_first ? q : p;
    precise const double ex = other.x - base.x, ey = other.y - base.y;
    precise const double dx = q.x - p.x, dy = q.y - p.y;
    const bool owns = dy < 0.0 || (dy == 0.0 && dx > 0.0);
    precise const double e = ex * (py - base.y) - ey * (px - base.x);
    w[i] = p_first ? e : -e;
    if (!(w[i] > 0.0 || (w[i] == 0.0 && owns))) return false;
  }
  precise const double inv_area = 1.0 / abs(area);
  precise const double interpolated = (w[0] * v[0].z + w[1] * v[1].z + w[2] * v[2].z) * inv_area;
  inv_w = interpolated;
  return true;
}

void main() {
  ScreenPolys polys = pc.polys;
  const int count = polys.p[triangle].count;
  const double px = double(floor(gl_FragCoord.x)) + 0.5, py = double(floor(gl_FragCoord.y)) + 0.5;
  float depth = 3.40282347e38;  // kEmptyDepth
  bool hit = false;
  for (int k = 1; k + 1 < count; ++k) {
    double inv_w;
    if (!covers(polys.p[triangle].v[0], polys.p[triangle].v[k], polys.p[triangle].v[k + 1], px,
                py, inv_w) ||
        !(inv_w > 0.0))
      continue;
    precise const double d = 1.0 / inv_w;
    depth = min(depth, float(d));
    hit = true;
  }
  if (!hit) discard;
  stored_depth = depth;
  gl_FragDepth = depth * pc.depth_scale;
}
