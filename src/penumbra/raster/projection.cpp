#include "penumbra/raster/projection.hpp"

#include <algorithm>
#include <cmath>

namespace penumbra {

Projection camera_projection(const Camera& camera) {
  Projection p;
  p.eye = DVec3(camera.position);
  p.forward = glm::normalize(DVec3(camera.target) - DVec3(camera.position));
  p.right = glm::normalize(glm::cross(p.forward, DVec3(camera.up)));
  p.up = glm::cross(p.right, p.forward);
  p.tan_half_y = std::tan(0.5 * camera.vfov_deg * kPi / 180.0);
  p.tan_half_x =
      p.tan_half_y * static_cast<double>(camera.width) / static_cast<double>(camera.height);
  p.width = camera.width;
  p.height = camera.height;
  return p;
}

Projection look_projection(const DVec3& eye, const DVec3& forward, double tan_half_y, int width,
                           int height) {
  Projection p;
  p.eye = eye;
  p.forward = glm::normalize(forward);
  Vec3 t, b;
  orthonormal_basis(Vec3(p.forward), t, b);
  // Re-orthonormalise in double from the float basis.
  p.right = glm::normalize(DVec3(t) - glm::dot(DVec3(t), p.forward) * p.forward);
  p.up = glm::cross(p.right, p.forward);
  p.tan_half_y = tan_half_y;
  p.tan_half_x = tan_half_y * static_cast<double>(width) / static_cast<double>(height);
  p.width = width;
  p.height = height;
  return p;
}

namespace {

bool lex_less(const DVec4& a, const DVec4& b) {
  if (a.x != b.x) return a.x < b.x;
  if (a.y != b.y) return a.y < b.y;
  if (a.z != b.z) return a.z < b.z;
  return a.w < b.w;
}

/// Signed distance-like value of clip-space plane `plane` (0 near, 1..4 sides) at c.
double plane_value(int plane, const DVec4& c, double near, double guard) {
  switch (plane) {
    case 0:
      return c.w - near * c.z;
    case 1:
      return guard * c.w - c.x;
    case 2:
      return guard * c.w + c.x;
    case 3:
      return guard * c.w - c.y;
    default:
      return guard * c.w + c.y;
  }
}

int clip_one(int plane, const DVec4* in, int n, double near, double guard, DVec4* out) {
  int m = 0;
  for (int i = 0; i < n; ++i) {
    const DVec4& p = in[i];
    const DVec4& q = in[(i + 1) % n];
    const double fp = plane_value(plane, p, near, guard), fq = plane_value(plane, q, near, guard);
    if (fp >= 0.0) out[m++] = p;
    if ((fp >= 0.0) != (fq >= 0.0)) {
      // Canonical order: the same edge gives the same point whichever polygon clips it.
      const bool p_first = lex_less(p, q);
      const DVec4& a = p_first ? p : q;
      const DVec4& b = p_first ? q : p;
      const double fa = p_first ? fp : fq, fb = p_first ? fq : fp;
      out[m++] = a + (fa / (fa - fb)) * (b - a);
    }
  }
  return m;
}

}  // namespace

int clip_polygon(const DVec4* in, int n, double near, double guard, DVec4* out) {
  DVec4 buf[2][kMaxClipVertices];
  int m = n;
  for (int i = 0; i < n; ++i) buf[0][i] = in[i];
  int cur = 0;
  for (int plane = 0; plane < 5 && m >= 3; ++plane) {
    m = clip_one(plane, buf[cur], m, near, guard, buf[cur ^ 1]);
    cur ^= 1;
  }
  if (m < 3) return 0;
  for (int i = 0; i < m; ++i) out[i] = buf[cur][i];
  return m;
}

ScreenPolygon project_polygon(const Projection& proj, const DVec4* world, int n, double near,
                              double guard) {
  DVec4 clip[kMaxClipVertices], clipped[kMaxClipVertices];
  for (int i = 0; i < n; ++i) clip[i] = proj.to_clip(world[i]);
  ScreenPolygon poly;
  const int m = clip_polygon(clip, n, near, guard, clipped);
  if (m < 3) return poly;
  poly.count = m;
  poly.xmin = poly.ymin = kInfinity;
  poly.xmax = poly.ymax = -kInfinity;
  for (int i = 0; i < m; ++i) {
    if (!(clipped[i].w > 0.0)) {
      // Only a zero direction can get here; stay conservative: the whole (guard-banded) screen.
      const double gx = guard * proj.width, gy = guard * proj.height;
      poly.count = 4;
      poly.v[0] = {-gx, -gy, 0.0};
      poly.v[1] = {gx + proj.width, -gy, 0.0};
      poly.v[2] = {gx + proj.width, gy + proj.height, 0.0};
      poly.v[3] = {-gx, gy + proj.height, 0.0};
      poly.xmin = -gx, poly.ymin = -gy, poly.xmax = gx + proj.width, poly.ymax = gy + proj.height;
      return poly;
    }
    poly.v[i] = proj.to_screen(clipped[i]);
    poly.xmin = std::min(poly.xmin, poly.v[i].x);
    poly.xmax = std::max(poly.xmax, poly.v[i].x);
    poly.ymin = std::min(poly.ymin, poly.v[i].y);
    poly.ymax = std::max(poly.ymax, poly.v[i].y);
  }
  return poly;
}

bool polygon_row_span(const ScreenPolygon& poly, double y0, double y1, double& x0, double& x1) {
  if (poly.empty() || poly.ymax < y0 || poly.ymin > y1) return false;
  double lo = kInfinity, hi = -kInfinity;
  for (int i = 0; i < poly.count; ++i) {
    const DVec3& p = poly.v[i];
    const DVec3& q = poly.v[(i + 1) % poly.count];
    // The part of edge pq with y in [y0, y1].
    const double pymin = std::min(p.y, q.y), pymax = std::max(p.y, q.y);
    if (pymax < y0 || pymin > y1) continue;
    if (p.y == q.y) {
      lo = std::min({lo, p.x, q.x});
      hi = std::max({hi, p.x, q.x});
      continue;
    }
    const double ta = std::clamp((y0 - p.y) / (q.y - p.y), 0.0, 1.0);
    const double tb = std::clamp((y1 - p.y) / (q.y - p.y), 0.0, 1.0);
    const double xa = p.x + ta * (q.x - p.x), xb = p.x + tb * (q.x - p.x);
    lo = std::min({lo, xa, xb});
    hi = std::max({hi, xa, xb});
  }
  if (lo > hi) return false;
  x0 = lo;
  x1 = hi;
  return true;
}

}  // namespace penumbra
