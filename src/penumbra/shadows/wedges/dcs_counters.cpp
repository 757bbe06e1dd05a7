#include "penumbra/shadows/wedges/dcs_counters.hpp"

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

}  // namespace

bool covered_region(const DVec2& a, const DVec2& b, CoveredRegion& r, int& turn) {
  const DVec2 c(0.5, 0.5);
  const double o = cross2(a - c, b - c);
  if (o != 0.0) {
    const double sg = o > 0.0 ? 1.0 : -1.0;
    half_plane(r, 0, c, a - c, sg);  // counter-clockwise (for sg = +1) of c → a
    half_plane(r, 1, c, c - b, sg);  // clockwise of c → b: sg · cross(s − c, b − c) ≥ 0
    half_plane(r, 2, a, b - a, sg);  // beyond the line: sg · cross(b − a, s − a) < 0
    turn = o > 0.0 ? 1 : -1;
    return true;
  }
  // c on the line ab [Forest §4.4.3]: a half-plane if c lies inside the segment, else nothing.
  if (!(glm::dot(a - c, b - c) < 0.0)) return false;
  // The walk starts from c + εd: (c + εd, a, b) turns as cross(b − a, d).
  double side = cross2(b - a, DVec2(0.6180339887498949, 1.0));
  if (side == 0.0) side = cross2(b - a, DVec2(1.0, 0.0));
  const double sg = side > 0.0 ? 1.0 : -1.0;
  for (int k = 0; k < 2; ++k) r.a[k] = r.b[k] = 0.0f, r.c[k] = 1.0f;  // always true
  half_plane(r, 2, a, b - a, sg);
  turn = side > 0.0 ? 1 : -1;
  return true;
}

}  // namespace penumbra::dcs
