#version 460
// Triangle setup of the exact depth pass (depth_exact.glsl): face selection, projection, near and
// guard-band clipping and the screen transform of project_polygon, operation for operation in
// double (`precise`: no contraction), so the screen vertices equal the CPU's.
#include "common.glsl"
#include "depth_exact.glsl"

layout(buffer_reference, scalar) buffer View {
  dvec3 eye;
  dvec3 right;
  dvec3 up;
  dvec3 forward;
  double tan_half_x;
  double tan_half_y;
  double resolution;
  double near;
  int faces;  // 0 front, 1 back, 2 both (FaceSelect)
};

layout(push_constant) uniform Push {
  Vec4s vertices;
  View view;
  ScreenPolys polys;
  uint n;
} pc;

const double kGuard = 1.01;  // project_polygon's default guard band

precise double dot3(dvec3 a, dvec3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }

precise dvec3 cross3(dvec3 x, dvec3 y) {
  return dvec3(x.y * y.z - y.y * x.z, x.z * y.x - y.z * x.x, x.x * y.y - y.x * x.y);
}

precise double plane_value(int plane, dvec4 c, double near) {
  if (plane == 0) return c.w - near * c.z;
  if (plane == 1) return kGuard * c.w - c.x;
  if (plane == 2) return kGuard * c.w + c.x;
  if (plane == 3) return kGuard * c.w - c.y;
  return kGuard * c.w + c.y;
}

bool lex_less(dvec4 a, dvec4 b) {
  if (a.x != b.x) return a.x < b.x;
  if (a.y != b.y) return a.y < b.y;
  if (a.z != b.z) return a.z < b.z;
  return a.w < b.w;
}

void main() {
  const uint t = global_id();
  if (t >= pc.n) return;
  View view = pc.view;
  pc.polys.p[t].count = 0;
  precise dvec3 p[3];
  for (int c = 0; c < 3; ++c) p[c] = dvec3(pc.vertices.v[3u * t + uint(c)].xyz);
  precise const double side = dot3(cross3(p[1] - p[0], p[2] - p[0]), view.eye - p[0]);
  if (side == 0.0 || (view.faces == 0 && side < 0.0) || (view.faces == 1 && side > 0.0)) return;

  // Projection::to_clip (world w = 1): clip z carries the world w.
  dvec4 poly[2][kMaxPolyVertices];
  for (int c = 0; c < 3; ++c) {
    precise const dvec3 rel = p[c] - view.eye;
    precise const double x = dot3(rel, view.right) / view.tan_half_x;
    precise const double y = dot3(rel, view.up) / view.tan_half_y;
    poly[0][c] = dvec4(x, y, 1.0, dot3(rel, view.forward));
  }
  // clip_polygon: Sutherland–Hodgman on the near plane and the four guard-band side planes, each
  // crossing computed from the edge's lexicographically smaller endpoint.
  int m = 3, cur = 0;
  for (int plane = 0; plane < 5 && m >= 3; ++plane) {
    int out_n = 0;
    for (int i = 0; i < m; ++i) {
      const dvec4 a = poly[cur][i], b = poly[cur][(i + 1) % m];
      const double fa = plane_value(plane, a, view.near), fb = plane_value(plane, b, view.near);
      if (fa >= 0.0) poly[cur ^ 1][out_n++] = a;
      if ((fa >= 0.0) != (fb >= 0.0)) {
        const bool a_first = lex_less(a, b);
        const dvec4 lo = a_first ? a : b, hi = a_first ? b : a;
        const double flo = a_first ? fa : fb, fhi = a_first ? fb : fa;
        precise const double s = flo / (flo - fhi);
        precise const dvec4 crossing = lo + s * (hi - lo);
        poly[cur ^ 1][out_n++] = crossing;
      }
    }
    m = out_n;
    cur ^= 1;
  }
  if (m < 3) return;
  // Projection::to_screen; a vertex with w ≤ 0 (a zero direction) makes the CPU take the whole
  // guard-banded screen.
  const double res = view.resolution;
  ScreenPoly sp;
  sp.count = m;
  double xmin = 1e300, xmax = -1e300, ymin = 1e300, ymax = -1e300;
  for (int i = 0; i < m; ++i) {
    const dvec4 c = poly[cur][i];
    if (!(c.w > 0.0)) {
      const double g = kGuard * res;
      sp.count = 4;
      sp.v[0] = dvec3(-g, -g, 0.0);
      sp.v[1] = dvec3(g + res, -g, 0.0);
      sp.v[2] = dvec3(g + res, g + res, 0.0);
      sp.v[3] = dvec3(-g, g + res, 0.0);
      xmin = ymin = -g;
      xmax = ymax = g + res;
      break;
    }
    precise const double inv_w = 1.0 / c.w;
    precise const double sx = (0.5 + 0.5 * c.x * inv_w) * res;
    precise const double sy = (0.5 - 0.5 * c.y * inv_w) * res;
    sp.v[i] = dvec3(sx, sy, inv_w);
    xmin = min(xmin, sx), xmax = max(xmax, sx), ymin = min(ymin, sy), ymax = max(ymax, sy);
  }
  if (xmax < 0.0 || ymax < 0.0 || xmin > res || ymin > res) return;
  // rasterize_triangle's scan box of the polygon (the union of its fan pieces' boxes).
  const int last = int(res) - 1;
  sp.x0 = max(0, int(floor(xmin - 0.5)));
  sp.y0 = max(0, int(floor(ymin - 0.5)));
  sp.x1 = min(last, int(ceil(xmax - 0.5)));
  sp.y1 = min(last, int(ceil(ymax - 0.5)));
  if (sp.x0 > sp.x1 || sp.y0 > sp.y1) return;
  pc.polys.p[t] = sp;
}
