#include "penumbra/shadows/wedges/dcs_counters.hpp"

#include <algorithm>
#include <cmath>

namespace penumbra::dcs {

namespace {

double cross2(const DVec2& x, const DVec2& y) {
  return x.x * y.y - x.y * y.x;
}

/// h(s) = sign · cross(dir, s − origin) as affine coefficients.
void half_plane(CoveredRegion& r, int k, const DVec2& origin, const DVec2& dir, double sign) {
  const double a = -sign * dir.y, b = sign * dir.x;
  r.a[k] = static_cast<float>(a);
  r.b[k] = static_cast<float>(b);
  r.c[k] = static_cast<float>(-(a * origin.x + b * origin.y));
}

/// The v extent of sector(c; a, b) ∩ [0,1]² (angle below π): a, b, where the rays c → a and
/// c → b leave the square, and the corners between them.
void sector_v_range(const DVec2& c, const DVec2& a, const DVec2& b, double sg, CoveredRegion& r) {
  double lo = std::min(a.y, b.y), hi = std::max(a.y, b.y);
  for (const DVec2& p : {a, b}) {
    const DVec2 d = p - c;
    const double m = std::max(std::abs(d.x), std::abs(d.y));
    if (m > 0.0) {
      const double y = c.y + 0.5 / m * d.y;
      lo = std::min(lo, y), hi = std::max(hi, y);
    }
  }
  for (const DVec2 corner : {DVec2(0, 0), DVec2(1, 0), DVec2(0, 1), DVec2(1, 1)})
    if (sg * cross2(a - c, corner - c) >= 0.0 && sg * cross2(corner - c, b - c) >= 0.0)
      lo = std::min(lo, corner.y), hi = std::max(hi, corner.y);
  r.v_lo = std::max(0.0, lo);
  r.v_hi = std::min(1.0, hi);
}

}  // namespace

bool covered_region(const DVec2& a, const DVec2& b, CoveredRegion& r, int& turn) {
  const DVec2 c(0.5, 0.5);
  const double o = cross2(a - c, b - c);
  if (o != 0.0) {
    const double sg = o > 0.0 ? 1.0 : -1.0;
    half_plane(r, 0, c, a - c, sg);  // counter-clockwise (for sg = +1) of c → a
    half_plane(r, 1, c, c - b, sg);  // clockwise of c → b: sg · cross(s − c, b − c) ≥ 0
    half_plane(r, 2, a, b - a, sg);  // beyond the line: sg · cross(b − a, s − a) < 0
    sector_v_range(c, a, b, sg, r);
    // A sample s = c + λ·d on a ray (λ > 0) turned counter-clockwise by ε moves along rot90(d):
    // h_0 changes by sg·ελ|d|², h_1 (direction −d) by −sg·ελ|d|².
    r.closed[0] = sg > 0.0;
    r.closed[1] = sg < 0.0;
    turn = o > 0.0 ? 1 : -1;
    return true;
  }
  // c on the line ab [Forest 2008 §4.4.3]: a half-plane if c lies inside the segment, else nothing.
  if (!(glm::dot(a - c, b - c) < 0.0)) return false;
  // The walk starts from c + εd: (c + εd, a, b) turns as cross(b − a, d).
  double side = cross2(b - a, DVec2(0.6180339887498949, 1.0));
  if (side == 0.0) side = cross2(b - a, DVec2(1.0, 0.0));
  const double sg = side > 0.0 ? 1.0 : -1.0;
  for (int k = 0; k < 2; ++k) r.a[k] = r.b[k] = 0.0f, r.c[k] = 1.0f;  // always true
  half_plane(r, 2, a, b - a, sg);
  r.v_lo = 0.0, r.v_hi = 1.0;
  turn = side > 0.0 ? 1 : -1;
  return true;
}

}  // namespace penumbra::dcs
