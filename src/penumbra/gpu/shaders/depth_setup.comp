#version 460
// Triangle setup of the exact depth pass (depth_exact.glsl): face selection, projection, near and
// guard-band clipping and the screen transform of project_polygon (clip.glsl), so the screen
// vertices equal the CPU's.
#include "common.glsl"
#include "depth_exact.glsl"
#include "clip.glsl"

layout(buffer_reference, scalar) buffer View {
  ClipView clip;
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

void main() {
  const uint t = global_id();
  if (t >= pc.n) return;
  View view = pc.view;
  const ClipView cv = view.clip;
  pc.polys.p[t].count = 0;
  precise dvec3 p[3];
  for (int c = 0; c < 3; ++c) p[c] = dvec3(pc.vertices.v[3u * t + uint(c)].xyz);
  precise const double side = dot3(cross3(p[1] - p[0], p[2] - p[0]), cv.eye - p[0]);
  if (side == 0.0 || (view.faces == 0 && side < 0.0) || (view.faces == 1 && side > 0.0)) return;

  dvec4 poly[kMaxClipVertices];
  for (int c = 0; c < 3; ++c) poly[c] = to_clip(cv, dvec4(p[c], 1.0));
  const int m = clip_polygon(poly, 3, view.near, kGuard);
  if (m < 3) return;
  // A vertex with w ≤ 0 (a zero direction) makes the CPU take the whole guard-banded screen.
  const double res = cv.width;
  ScreenPoly sp;
  sp.count = m;
  double xmin = 1e300, xmax = -1e300, ymin = 1e300, ymax = -1e300;
  for (int i = 0; i < m; ++i) {
    if (!(poly[i].w > 0.0)) {
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
    sp.v[i] = to_screen(cv, poly[i]);
    xmin = min(xmin, sp.v[i].x), xmax = max(xmax, sp.v[i].x);
    ymin = min(ymin, sp.v[i].y), ymax = max(ymax, sp.v[i].y);
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
