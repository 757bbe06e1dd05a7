// raster/projection.cpp in double, operation for operation (`precise`: no contraction), so that a
// polygon projected here has the CPU's screen vertices: Projection::to_clip / to_screen and
// clip_polygon (Sutherland–Hodgman on the near plane w ≥ near·w_world and the guard-banded side
// planes, each crossing computed from the edge's lexicographically smaller endpoint). Needs
// GL_EXT_shader_explicit_arithmetic_types_float64.

/// kMaxClipVertices of raster/projection.hpp.
const int kMaxClipVertices = 9;

struct ClipView {
  dvec3 eye, right, up, forward;
  double tan_half_x, tan_half_y;
  double width, height;
};

precise double dot3(dvec3 a, dvec3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }

precise dvec3 cross3(dvec3 x, dvec3 y) {
  return dvec3(x.y * y.z - y.y * x.z, x.z * y.x - y.z * x.x, x.x * y.y - y.x * x.y);
}

/// Homogeneous world point (w = 1) or direction (w = 0) to clip space (z = the world w).
precise dvec4 to_clip(ClipView v, dvec4 world) {
  const dvec3 rel = world.xyz - v.eye * world.w;
  return dvec4(dot3(rel, v.right) / v.tan_half_x, dot3(rel, v.up) / v.tan_half_y, world.w,
               dot3(rel, v.forward));
}

/// Clip (w > 0) to screen pixels (y down) and z = 1/w.
precise dvec3 to_screen(ClipView v, dvec4 c) {
  const double inv_w = 1.0 / c.w;
  return dvec3((0.5 + 0.5 * c.x * inv_w) * v.width, (0.5 - 0.5 * c.y * inv_w) * v.height, inv_w);
}

precise double plane_value(int plane, dvec4 c, double near, double guard) {
  if (plane == 0) return c.w - near * c.z;
  if (plane == 1) return guard * c.w - c.x;
  if (plane == 2) return guard * c.w + c.x;
  if (plane == 3) return guard * c.w - c.y;
  return guard * c.w + c.y;
}

bool lex_less(dvec4 a, dvec4 b) {
  if (a.x != b.x) return a.x < b.x;
  if (a.y != b.y) return a.y < b.y;
  if (a.z != b.z) return a.z < b.z;
  return a.w < b.w;
}

/// Clips poly[0..n) in place; returns the vertex count (< 3: nothing left).
int clip_polygon(inout dvec4 poly[kMaxClipVertices], int n, double near, double guard) {
  dvec4 next[kMaxClipVertices];
  int m = n;
  for (int plane = 0; plane < 5 && m >= 3; ++plane) {
    int out_n = 0;
    for (int i = 0; i < m; ++i) {
      const dvec4 a = poly[i], b = poly[(i + 1) % m];
      const double fa = plane_value(plane, a, near, guard), fb = plane_value(plane, b, near, guard);
      if (fa >= 0.0) next[out_n++] = a;
      if ((fa >= 0.0) != (fb >= 0.0)) {
        const bool a_first = lex_less(a, b);
        const dvec4 lo = a_first ? a : b, hi = a_first ? b : a;
        const double flo = a_first ? fa : fb, fhi = a_first ? fb : fa;
        precise const double s = flo / (flo - fhi);
        precise const dvec4 crossing = lo + s * (hi - lo);
        next[out_n++] = crossing;
      }
    }
    m = out_n;
    for (int i = 0; i < m; ++i) poly[i] = next[i];
  }
  return m;
}
