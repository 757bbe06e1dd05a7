#include "penumbra/shadows/wedges/coverage.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "penumbra/core/parallel.hpp"
#include "penumbra/shadows/exact/projection.hpp"

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
  // An unclipped end is the vertex itself, not A + 1·(B − A), which can round to a neighbouring
  // point: two silhouette edges that share a vertex must project it to the same uv, or the ray
  // from the centre through it bounds their covered regions with a gap or an overlap.
  const DVec3 P = t0 == 0.0 ? A : A + t0 * (B - A), Q = t1 == 1.0 ? B : A + t1 * (B - A);
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

BoxSector box_sector(const DVec2& lo, const DVec2& hi, const DVec2& a, const DVec2& b) {
  const DVec2 c(0.5);
  const DVec2 da = a - c, db = b - c;
  BoxSector out;
  out.tri2 = cross2(da, db);
  if (out.tri2 == 0.0) return out;
  const double s = out.tri2 > 0.0 ? 1.0 : -1.0;
  // Where the ray c + λ·d leaves the box (λ ≥ 0; the box holds c).
  const auto exit = [&](const DVec2& d) {
    double lambda = kInfinity;
    for (int k = 0; k < 2; ++k) {
      if (d[k] > 0.0) lambda = std::min(lambda, (hi[k] - c[k]) / d[k]);
      if (d[k] < 0.0) lambda = std::min(lambda, (lo[k] - c[k]) / d[k]);
    }
    return c + lambda * d;
  };
  out.outline[out.n++] = exit(da);
  // Corners strictly inside the sector (at most two, as its angle is below π), in angular order.
  DVec2 corners[2];
  int m = 0;
  for (const DVec2& k : {lo, DVec2(hi.x, lo.y), hi, DVec2(lo.x, hi.y)}) {
    const DVec2 dk = k - c;
    if (m < 2 && s * cross2(da, dk) > 0.0 && s * cross2(dk, db) > 0.0) corners[m++] = k;
  }
  if (m == 2 && s * cross2(corners[0] - c, corners[1] - c) < 0.0) std::swap(corners[0], corners[1]);
  for (int i = 0; i < m; ++i) out.outline[out.n++] = corners[i];
  out.outline[out.n++] = exit(db);
  // The fan from c: every triangle (c, p_i, p_i+1) turns with s.
  for (int i = 0; i + 1 < out.n; ++i)
    out.area2 += s * cross2(out.outline[i] - c, out.outline[i + 1] - c);
  return out;
}

double square_sector_minus_triangle(const DVec2& a, const DVec2& b) {
  return box_sector(DVec2(0.0), DVec2(1.0), a, b).minus_triangle();
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

LightEmission::LightEmission(const Texture& tex, const Vec3& radiance)
    : width(std::max(1, tex.width)), height(std::max(1, tex.height)) {
  density.assign(static_cast<size_t>(width) * height, DVec3(0.0));
  if (tex.width <= 0 || tex.height <= 0 || tex.texels.empty()) {
    std::fill(density.begin(), density.end(), DVec3(1.0));
    total = DVec3(radiance);
    max_density = DVec3(1.0);
    return;
  }
  const double texel_area = 1.0 / (static_cast<double>(width) * height);
  for (int ty = 0; ty < height; ++ty)
    for (int tx = 0; tx < width; ++tx) {
      // As exact/exact_scene.cpp and light_weights.hpp: RGB (grey for one channel) × radiance.
      const DVec3 rgb = tex.channels < 3 ? DVec3(tex.channel(tx, ty, 0))
                                         : DVec3(tex.channel(tx, ty, 0), tex.channel(tx, ty, 1),
                                                 tex.channel(tx, ty, 2));
      const DVec3 e = rgb * DVec3(radiance);
      density[static_cast<size_t>(ty) * width + tx] = e;
      total += e * texel_area;
    }
  for (DVec3& d : density)
    for (int c = 0; c < 3; ++c) {
      d[c] = total[c] > 0.0 ? d[c] / total[c] : 0.0;
      max_density[c] = std::max(max_density[c], d[c]);
    }
}

namespace {

/// Keeps the part of the convex polygon where f(x) ≥ 0 (f affine). At most 16 vertices.
template <class F>
int clip_poly(DVec2* poly, int n, F&& f) {
  DVec2 tmp[16];
  int m = 0;
  for (int i = 0; i < n && m < 15; ++i) {
    const DVec2 &p = poly[i], &q = poly[(i + 1) % n];
    const double fp = f(p), fq = f(q);
    if (fp >= 0.0) tmp[m++] = p;
    if ((fp >= 0.0) != (fq >= 0.0)) tmp[m++] = p + (fp / (fp - fq)) * (q - p);
  }
  for (int i = 0; i < m; ++i) poly[i] = tmp[i];
  return m;
}

double poly_area(const DVec2* poly, int n) {
  double a2 = 0.0;
  for (int i = 0; i < n; ++i) a2 += cross2(poly[i], poly[(i + 1) % n]);
  return 0.5 * std::abs(a2);
}

/// The texels [i0, i1] of a row (or column) of w that [l, h] ⊂ [0, 1] reaches.
void texel_range(double l, double h, int w, int& i0, int& i1) {
  i0 = std::clamp(static_cast<int>(std::floor(l * w)), 0, w - 1);
  i1 = std::clamp(static_cast<int>(std::ceil(h * w)) - 1, i0, w - 1);
}

/// Σ over texels of density × area(poly ∩ texel), the convex polygon poly inside [0,1]².
DVec3 weigh_polygon(const LightEmission& em, const DVec2* poly, int n) {
  DVec3 sum(0.0);
  if (n < 3) return sum;
  DVec2 lo(1.0), hi(0.0);
  for (int i = 0; i < n; ++i) {
    lo = glm::min(lo, poly[i]);
    hi = glm::max(hi, poly[i]);
  }
  int x0, x1, y0, y1;
  texel_range(lo.x, hi.x, em.width, x0, x1);
  texel_range(lo.y, hi.y, em.height, y0, y1);
  if (x0 == x1 && y0 == y1)
    return em.density[static_cast<size_t>(y0) * em.width + x0] * poly_area(poly, n);
  for (int ty = y0; ty <= y1; ++ty)
    for (int tx = x0; tx <= x1; ++tx) {
      const double u0 = static_cast<double>(tx) / em.width,
                   u1 = static_cast<double>(tx + 1) / em.width,
                   v0 = static_cast<double>(ty) / em.height,
                   v1 = static_cast<double>(ty + 1) / em.height;
      DVec2 q[16];
      for (int i = 0; i < n; ++i) q[i] = poly[i];
      int m = n;
      // The outermost texels reach to the square's border (the polygon is inside it anyway).
      if (tx > 0) m = clip_poly(q, m, [&](const DVec2& p) { return p.x - u0; });
      if (m >= 3 && tx < em.width - 1)
        m = clip_poly(q, m, [&](const DVec2& p) { return u1 - p.x; });
      if (m >= 3 && ty > 0) m = clip_poly(q, m, [&](const DVec2& p) { return p.y - v0; });
      if (m >= 3 && ty < em.height - 1)
        m = clip_poly(q, m, [&](const DVec2& p) { return v1 - p.y; });
      if (m >= 3) sum += em.density[static_cast<size_t>(ty) * em.width + tx] * poly_area(q, m);
    }
  return sum;
}

/// The unsigned weighted region of the branch `sign` (+1: c left of a→b, region right of a→b;
/// −1: the mirror). With c on the segment (tri2 = 0, c between a and b) the branch's limit: the
/// half of the square on the branch's side.
/// Whether c lies on the line of a→b up to rounding (relative 1e-12: the sector then differs from
/// a half-plane by an angle below 1e-12). One threshold for the table, its taps and the lookup,
/// so that the branch of a pair does not depend on how the compiler contracted the cross product.
bool through_line(const DVec2& da, const DVec2& db, double tri2) {
  return std::abs(tri2) <= 1e-12 * glm::length(da) * glm::length(db);
}

int branch_sign(const DVec2& a, const DVec2& b) {
  const DVec2 c(0.5), da = a - c, db = b - c;
  const double tri2 = cross2(da, db);
  if (through_line(da, db, tri2)) return glm::dot(da, db) < 0.0 ? 1 : 0;
  return tri2 > 0.0 ? 1 : -1;
}

/// The unsigned weighted region of the branch `sign` (+1: c left of a→b, region right of a→b;
/// −1: the mirror; the sign branch_sign gives). With c on the segment (up to rounding) the
/// branch's limit: the half of the square on the branch's side.
DVec3 weighted_region(const LightEmission& em, const DVec2& a, const DVec2& b, int sign) {
  const DVec2 c(0.5), da = a - c, db = b - c;
  const double tri2 = cross2(da, db);
  DVec2 poly[16];
  int n = 0;
  if (through_line(da, db, tri2)) {
    if (!(glm::dot(da, db) < 0.0)) return DVec3(0.0);
    poly[0] = DVec2(0.0);
    poly[1] = DVec2(1.0, 0.0);
    poly[2] = DVec2(1.0);
    poly[3] = DVec2(0.0, 1.0);
    n = 4;
  } else {
    // The sector's part of the square, counter-clockwise: c then its outline (reversed when
    // (c, a, b) turns clockwise).
    const BoxSector sector = box_sector(DVec2(0.0), DVec2(1.0), a, b);
    if (sector.tri2 == 0.0) return DVec3(0.0);
    poly[n++] = c;
    for (int i = 0; i < sector.n; ++i)
      poly[n++] = sector.outline[sector.tri2 > 0.0 ? i : sector.n - 1 - i];
  }
  if (n < 3) return DVec3(0.0);
  // The far side of the line a→b from c: right of a→b for sign > 0.
  const DVec2 d = b - a;
  n = clip_poly(poly, n, [&](const DVec2& p) { return -sign * cross2(d, p - a); });
  return weigh_polygon(em, poly, n);
}

}  // namespace

DVec3 emission_in_box(const LightEmission& em, const DVec2& lo_in, const DVec2& hi_in) {
  const DVec2 lo = glm::clamp(lo_in, DVec2(0.0), DVec2(1.0)),
              hi = glm::clamp(hi_in, DVec2(0.0), DVec2(1.0));
  if (!(hi.x > lo.x && hi.y > lo.y)) return DVec3(0.0);
  // A box meets a texel in a box: the product of the overlaps, no polygon clipping (the
  // outermost texels reach to the square's border, as in weigh_polygon).
  int x0, x1, y0, y1;
  texel_range(lo.x, hi.x, em.width, x0, x1);
  texel_range(lo.y, hi.y, em.height, y0, y1);
  DVec3 sum(0.0);
  for (int ty = y0; ty <= y1; ++ty) {
    const double v0 = ty > 0 ? std::max(lo.y, static_cast<double>(ty) / em.height) : lo.y;
    const double v1 =
        ty < em.height - 1 ? std::min(hi.y, static_cast<double>(ty + 1) / em.height) : hi.y;
    if (!(v1 > v0)) continue;
    for (int tx = x0; tx <= x1; ++tx) {
      const double u0 = tx > 0 ? std::max(lo.x, static_cast<double>(tx) / em.width) : lo.x;
      const double u1 =
          tx < em.width - 1 ? std::min(hi.x, static_cast<double>(tx + 1) / em.width) : hi.x;
      if (!(u1 > u0)) continue;
      sum += em.density[static_cast<size_t>(ty) * em.width + tx] * ((u1 - u0) * (v1 - v0));
    }
  }
  return sum;
}

DVec3 weighted_sector_minus_triangle(const LightEmission& em, const DVec2& a, const DVec2& b) {
  const double tri2 = cross2(a - DVec2(0.5), b - DVec2(0.5));
  if (tri2 == 0.0) return DVec3(0.0);
  const int s = tri2 > 0.0 ? 1 : -1;  // a through_line pair: the half on this side
  return static_cast<double>(s) * weighted_region(em, a, b, s);
}

CoverageTextureRGB::CoverageTextureRGB(int n, const LightEmission& em) : n_(std::max(2, n)) {
  const size_t m = static_cast<size_t>(n_);
  table_.resize(m * m * m * m * 3);
  const double h = 1.0 / (n_ - 1);
  parallel_rows(n_, [&](int ya) {
    size_t k = static_cast<size_t>(ya) * m * m * m * 3;
    for (int xa = 0; xa < n_; ++xa)
      for (int yb = 0; yb < n_; ++yb)
        for (int xb = 0; xb < n_; ++xb) {
          const DVec2 a(xa * h, ya * h), b(xb * h, yb * h);
          const int s = branch_sign(a, b);
          const DVec3 f = s ? weighted_region(em, a, b, s) : DVec3(0.0);
          for (int c = 0; c < 3; ++c) table_[k++] = static_cast<float>(f[c]);
        }
  });
}

DVec3 CoverageTextureRGB::tap(int xa, int ya, int xb, int yb, int sign) const {
  const size_t m = static_cast<size_t>(n_);
  const size_t k = (((static_cast<size_t>(ya) * m + xa) * m + yb) * m + xb) * 3;
  const DVec3 v(table_[k], table_[k + 1], table_[k + 2]);
  const double h = 1.0 / (n_ - 1);
  const DVec2 a(xa * h, ya * h), b(xb * h, yb * h);
  const int st = branch_sign(a, b);
  // A tap across the through-c line: continue the lookup's branch (the complement region).
  if (st != 0 && st != sign && glm::dot(a - DVec2(0.5), b - DVec2(0.5)) < 0.0)
    return DVec3(1.0) - v;
  return v;
}

DVec3 CoverageTextureRGB::sector_minus_triangle(const DVec2& a, const DVec2& b,
                                                CoverageTexture::Lookup lookup) const {
  const double tri2 = cross2(a - DVec2(0.5), b - DVec2(0.5));
  if (tri2 == 0.0) return DVec3(0.0);
  const int s = tri2 > 0.0 ? 1 : -1;
  int bx, by;
  double tx, ty;
  cell(b.x, n_, bx, tx);
  cell(b.y, n_, by, ty);
  const auto bilinear_b = [&](int xa, int ya) {
    return (1.0 - ty) * ((1.0 - tx) * tap(xa, ya, bx, by, s) + tx * tap(xa, ya, bx + 1, by, s)) +
           ty * ((1.0 - tx) * tap(xa, ya, bx, by + 1, s) + tx * tap(xa, ya, bx + 1, by + 1, s));
  };
  DVec3 v;
  if (lookup == CoverageTexture::Lookup::bilinear) {
    const auto nearest = [&](double u) {
      return static_cast<int>(std::lround(std::clamp(u, 0.0, 1.0) * (n_ - 1)));
    };
    v = bilinear_b(nearest(a.x), nearest(a.y));
  } else {
    int ax, ay;
    double sx, sy;
    cell(a.x, n_, ax, sx);
    cell(a.y, n_, ay, sy);
    v = (1.0 - sy) * ((1.0 - sx) * bilinear_b(ax, ay) + sx * bilinear_b(ax + 1, ay)) +
        sy * ((1.0 - sx) * bilinear_b(ax, ay + 1) + sx * bilinear_b(ax + 1, ay + 1));
  }
  return static_cast<double>(s) * v;
}

namespace {

double texture_bound(const DVec2& a, const DVec2& b, int n, CoverageTexture::Lookup lookup,
                     double tri_coef, double scale) {
  const double h = 1.0 / (std::max(2, n) - 1);
  const auto L = [&](const DVec2& p, double shift) {
    const double d = glm::length(p - DVec2(0.5)) - shift;
    return d > 0.0 ? scale * (0.25 / d + tri_coef) : std::numeric_limits<double>::infinity();
  };
  const double s2 = std::sqrt(2.0);
  if (lookup == CoverageTexture::Lookup::bilinear)
    return h * (L(a, h / s2) / s2 + s2 * L(b, s2 * h));
  return s2 * h * (L(a, s2 * h) + L(b, s2 * h));
}

}  // namespace

double coverage_texture_bound(const DVec2& a, const DVec2& b, int n,
                              CoverageTexture::Lookup lookup) {
  return texture_bound(a, b, n, lookup, 0.5 * std::sqrt(0.5), 1.0);
}

double coverage_texture_rgb_bound(const DVec2& a, const DVec2& b, int n,
                                  CoverageTexture::Lookup lookup, double rho_max) {
  return texture_bound(a, b, n, lookup, std::sqrt(0.5), rho_max);
}

}  // namespace penumbra
