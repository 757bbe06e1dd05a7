// The CPU depth-map rasterizer's screen polygons (raster/projection.cpp, raster/depth_map.cpp) on
// devices with shaderFloat64: depth_setup.comp projects, culls and clips every caster triangle in
// double exactly as project_polygon does; depth_map_exact.vert draws the polygon's pixel box and
// depth_map_exact.frag keeps the texel centres that rasterize_triangle's edge functions and
// top-left rule accept, with its 1/w interpolation. Hardware coverage (vertices snapped to a
// sub-texel grid) then no longer decides which texels a caster edge covers.
#extension GL_EXT_buffer_reference : require
#extension GL_EXT_scalar_block_layout : require
#extension GL_EXT_shader_explicit_arithmetic_types_float64 : require

/// kMaxClipVertices of raster/projection.hpp.
const int kMaxPolyVertices = 9;  // kMaxClipVertices

/// One caster triangle after projection and clipping: `count` screen vertices (x, y, 1/w), 0 when
/// culled; the pixel box the CPU scans, [x0, x1] × [y0, y1] inclusive.
struct ScreenPoly {
  dvec3 v[kMaxPolyVertices];
  int count;
  int x0, y0, x1, y1;
};
layout(buffer_reference, scalar) buffer ScreenPolys { ScreenPoly p[]; };

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

/// The nearest view depth of caster `t`'s fan pieces at texel centre (px, py); false if none covers
/// it. As rasterize_triangle: depth = 1 / the interpolated 1/w, rounded to float, the least wins.
bool nearest_depth(ScreenPolys polys, uint t, double px, double py, out float depth) {
  const int count = polys.p[t].count;
  depth = 3.40282347e38;  // kEmptyDepth
  bool hit = false;
  for (int k = 1; k + 1 < count; ++k) {
    double inv_w;
    if (!covers(polys.p[t].v[0], polys.p[t].v[k], polys.p[t].v[k + 1], px, py, inv_w) ||
        !(inv_w > 0.0))
      continue;
    precise const double d = 1.0 / inv_w;
    depth = min(depth, float(d));
    hit = true;
  }
  return hit;
}
