#include "penumbra/shadows/wedge_coverage.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "penumbra/shadows/exact_projection.hpp"

namespace penumbra {

namespace {

double cross2(const DVec2& a, const DVec2& b) {
  return a.x * b.y - a.y * b.x;
}

/// Liang–Barsky step for the constraint f(t) = fa + t·(fb − fa) ≥ 0 on t ∈ [t0, t1].
bool clip_linear(double fa, double fb, double& t0, double& t1) {
  if (fa >= 0.0 && fb >= 0.0) return true;
  if (fa < 0.0 && fb < 0.0) return false;
  const double t = fa / (fa - fb);
  if (fa < 0.0)
    t0 = std::max(t0, t);
  else
    t1 = std::min(t1, t);
  return t0 <= t1;
}

}  // namespace

bool clip_edge_to_light_square(const DVec3& A, const DVec3& B, DVec2& a, DVec2& b) {
  double t0 = 0.0, t1 = 1.0;
  // Each constraint is linear in the homogeneous point, hence in t (no perspective divide yet:
  // points at or behind the receiver's plane are clipped before they can blow up).
  if (!clip_linear(A.z - kMinW, B.z - kMinW, t0, t1)) return false;
  if (!clip_linear(1.0 - A.z, 1.0 - B.z, t0, t1)) return false;
  if (!clip_linear(A.x, B.x, t0, t1)) return false;
  if (!clip_linear(A.z - A.x, B.z - B.x, t0, t1)) return false;
  if (!clip_linear(A.y, B.y, t0, t1)) return false;
  if (!clip_linear(A.z - A.y, B.z - B.y, t0, t1)) return false;
  if (!(t0 < t1)) return false;
  const DVec3 P = A + t0 * (B - A), Q = A + t1 * (B - A);
  a = DVec2(P.x / P.z, P.y / P.z);
  b = DVec2(Q.x / Q.z, Q.y / Q.z);
  // Rounding in the divide may step a hair outside the square; the area formulas need inside.
  a = glm::clamp(a, 0.0, 1.0);
  b = glm::clamp(b, 0.0, 1.0);
  return true;
}

bool clip_edge_to_light_disk(DVec2& a, DVec2& b) {
  // |a − c + t·(b − a)|² ≤ r² on t ∈ [0, 1].
  const DVec2 c(0.5), d = b - a, f = a - c;
  const double qa = glm::dot(d, d), qb = 2.0 * glm::dot(f, d), qc = glm::dot(f, f) - 0.25;
  if (!(qa > 0.0)) return false;
  const double disc = qb * qb - 4.0 * qa * qc;
  if (!(disc > 0.0)) return false;
  const double s = std::sqrt(disc);
  const double t0 = std::max(0.0, (-qb - s) / (2.0 * qa)),
               t1 = std::min(1.0, (-qb + s) / (2.0 * qa));
  if (!(t0 < t1)) return false;
  const DVec2 na = a + t0 * d, nb = a + t1 * d;
  a = na;
  b = nb;
  return true;
}

int clip_box_to_sector(const DVec2& lo, const DVec2& hi, const DVec2& a, const DVec2& b,
                       DVec2 poly[8]) {
  const DVec2 c(0.5);
  const DVec2 da = a - c, db = b - c;
  const double tri2 = cross2(da, db);
  if (tri2 == 0.0) return 0;
  // The sector is the intersection of two half-planes through c (its angle is below π): clip the
  // box against them, oriented so the sector lies on the left of c→a and the right of c→b.
  const double s = tri2 > 0.0 ? 1.0 : -1.0;
  poly[0] = lo;
  poly[1] = DVec2(hi.x, lo.y);
  poly[2] = hi;
  poly[3] = DVec2(lo.x, hi.y);
  int n = 4;
  DVec2 tmp[8];
  const DVec2 dirs[2] = {da, db};
  for (int k = 0; k < 2; ++k) {
    const double sign = (k == 0 ? s : -s);
    int m = 0;
    for (int i = 0; i < n; ++i) {
      const DVec2 &p = poly[i], &q = poly[(i + 1) % n];
      const double fp = sign * cross2(dirs[k], p - c), fq = sign * cross2(dirs[k], q - c);
      if (fp >= 0.0) tmp[m++] = p;
      if ((fp >= 0.0) != (fq >= 0.0)) tmp[m++] = p + (fp / (fp - fq)) * (q - p);
    }
    n = m;
    for (int i = 0; i < n; ++i) poly[i] = tmp[i];
    if (n < 3) return n;
  }
  return n;
}

double square_sector_minus_triangle(const DVec2& a, const DVec2& b) {
  const DVec2 c(0.5);
  const double tri2 = cross2(a - c, b - c);  // twice the signed triangle area
  if (tri2 == 0.0) return 0.0;
  DVec2 poly[8];
  const int n = clip_box_to_sector(DVec2(0.0), DVec2(1.0), a, b, poly);
  if (n < 3) return 0.0;
  const double s = tri2 > 0.0 ? 1.0 : -1.0;
  double area2 = 0.0;
  for (int i = 0; i < n; ++i) area2 += cross2(poly[i], poly[(i + 1) % n]);
  // area2 > 0 (the square is counter-clockwise); the result carries the sector's orientation.
  return s * 0.5 * (std::abs(area2) - std::abs(tri2));
}

double disk_sector_minus_triangle(const DVec2& a, const DVec2& b) {
  const DVec2 c(0.5);
  const DVec2 da = a - c, db = b - c;
  const double cr = cross2(da, db);
  const double angle = std::atan2(cr, glm::dot(da, db));  // signed, in (−π, π]
  return 0.5 * (0.25 * angle - cr);
}

CoverageTexture::CoverageTexture(int n) : n_(std::max(2, n)) {
  const size_t m = static_cast<size_t>(n_);
  table_.resize(m * m * m * m);
  const double h = 1.0 / (n_ - 1);
  const DVec2 c(0.5);
  size_t k = 0;
  for (int ya = 0; ya < n_; ++ya)
    for (int xa = 0; xa < n_; ++xa)
      for (int yb = 0; yb < n_; ++yb)
        for (int xb = 0; xb < n_; ++xb) {
          const DVec2 a(xa * h, ya * h), b(xb * h, yb * h);
          double f = std::abs(square_sector_minus_triangle(a, b));
          // c on the segment (grid pairs symmetric about c): square_sector_minus_triangle says 0
          // (no orientation), but f's limit from either side is half the square.
          if (cross2(a - c, b - c) == 0.0 && glm::dot(a - c, b - c) < 0.0) f = 0.5;
          table_[k++] = static_cast<float>(f);
        }
}

namespace {

/// Grid cell and fraction of a uv coordinate on the nodes i / (n − 1).
void cell(double u, int n, int& i, double& t) {
  const double f = std::clamp(u, 0.0, 1.0) * (n - 1);
  i = std::min(static_cast<int>(f), n - 2);
  t = f - i;
}

}  // namespace

double CoverageTexture::bilinear_b(size_t sub, const DVec2& b) const {
  int ix, iy;
  double tx, ty;
  cell(b.x, n_, ix, tx);
  cell(b.y, n_, iy, ty);
  const size_t m = static_cast<size_t>(n_);
  const float* t = table_.data() + sub * m * m + static_cast<size_t>(iy) * m + ix;
  const double r0 = (1.0 - tx) * t[0] + tx * t[1], r1 = (1.0 - tx) * t[m] + tx * t[m + 1];
  return (1.0 - ty) * r0 + ty * r1;
}

double CoverageTexture::unsigned_coverage(const DVec2& a, const DVec2& b, Lookup lookup) const {
  const size_t m = static_cast<size_t>(n_);
  if (lookup == Lookup::bilinear) {
    const auto nearest = [&](double u) {
      return static_cast<size_t>(std::lround(std::clamp(u, 0.0, 1.0) * (n_ - 1)));
    };
    return bilinear_b(nearest(a.y) * m + nearest(a.x), b);
  }
  int ix, iy;
  double tx, ty;
  cell(a.x, n_, ix, tx);
  cell(a.y, n_, iy, ty);
  const size_t s = static_cast<size_t>(iy) * m + ix;
  const double r0 = (1.0 - tx) * bilinear_b(s, b) + tx * bilinear_b(s + 1, b);
  const double r1 = (1.0 - tx) * bilinear_b(s + m, b) + tx * bilinear_b(s + m + 1, b);
  return (1.0 - ty) * r0 + ty * r1;
}

double CoverageTexture::sector_minus_triangle(const DVec2& a, const DVec2& b, Lookup lookup) const {
  const double tri2 = cross2(a - DVec2(0.5), b - DVec2(0.5));
  if (tri2 == 0.0) return 0.0;
  return (tri2 > 0.0 ? 1.0 : -1.0) * unsigned_coverage(a, b, lookup);
}

double coverage_texture_bound(const DVec2& a, const DVec2& b, int n,
                              CoverageTexture::Lookup lookup) {
  const double h = 1.0 / (std::max(2, n) - 1), R = std::sqrt(0.5);
  const auto L = [&](const DVec2& p, double shift) {
    const double d = glm::length(p - DVec2(0.5)) - shift;
    return d > 0.0 ? 0.25 / d + 0.5 * R : std::numeric_limits<double>::infinity();
  };
  const double s2 = std::sqrt(2.0);
  if (lookup == CoverageTexture::Lookup::bilinear)
    return h * (L(a, h / s2) / s2 + s2 * L(b, s2 * h));
  return s2 * h * (L(a, s2 * h) + L(b, s2 * h));
}

}  // namespace penumbra
