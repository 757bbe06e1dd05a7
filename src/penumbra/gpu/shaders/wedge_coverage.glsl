// The wedge test and an edge's coverage of the light, shared by `wedges` and `wedge_blend` on
// Vulkan: shadows/wedges/geometry.hpp Wedge::contains and coverage.cpp box_sector,
// square_sector_minus_triangle and disk_sector_minus_triangle, operation for operation in double
// (`precise`: no contraction). GLSL has no double atan2: atan2_double evaluates it to a few ulps
// of std::atan2. Needs dcs.glsl.

const double kInfD = 1.0lf / 0.0lf;

/// One active pixel (gpu/wedge_pixels.hpp WedgePixelGpu): its shadow origin, light projection,
/// 1/uv area of its light frame, tile, flags (dcs.glsl kValid, kRound, kTauNeg), pixel index.
struct WedgePixel {
  dvec3 p, to_u, to_v, to_w;
  double inv_area;
  uint tile, flags, pixel, pad;
};
layout(buffer_reference, scalar) buffer WedgePixels { WedgePixel v[]; };

/// geometry.hpp Wedge::contains.
bool wedge_contains(Wedges wedges, uint w, dvec3 p) {
  const int count = wedges.v[w].plane_count;
  const double tol = wedges.v[w].tolerance;
  for (int i = 0; i < count; ++i) {
    const dvec4 plane = wedges.v[w].planes[i];
    precise const double lhs = dot3(plane.xyz, p);
    precise const double rhs = plane.w - tol;
    if (lhs < rhs) return false;
  }
  return true;
}

/// coverage.cpp BoxSector: the sector from c = (½, ½) spanned by a and b inside the box [lo, hi]
/// (which holds c): tri2 = cross(a − c, b − c), the outline without c (exit(a), corners, exit(b)),
/// and area(box ∩ sector) − area(c, a, b), signed by the turn.
struct BoxSector {
  double tri2, minus_triangle;
  int n;
  dvec2 outline[4];
};

BoxSector box_sector(dvec2 lo, dvec2 hi, dvec2 a, dvec2 b) {
  const dvec2 c = dvec2(0.5);
  precise const dvec2 da = a - c, db = b - c;
  BoxSector r;
  r.tri2 = cross2(da, db);
  r.minus_triangle = 0.0;
  r.n = 0;
  if (r.tri2 == 0.0) return r;
  const double s = r.tri2 > 0.0 ? 1.0 : -1.0;
  for (int e = 0; e < 2; ++e) {
    if (e == 1) {
      // Corners strictly inside the sector (at most two), in angular order.
      dvec2 corners[2];
      int m = 0;
      for (int k = 0; k < 4; ++k) {
        const dvec2 q = dvec2(k == 1 || k == 2 ? hi.x : lo.x, k >= 2 ? hi.y : lo.y);
        precise const dvec2 dk = q - c;
        precise const double s0 = s * cross2(da, dk), s1 = s * cross2(dk, db);
        if (m < 2 && s0 > 0.0 && s1 > 0.0) corners[m++] = q;
      }
      if (m == 2) {
        precise const double turn = s * cross2(corners[0] - c, corners[1] - c);
        if (turn < 0.0) {
          const dvec2 t = corners[0];
          corners[0] = corners[1];
          corners[1] = t;
        }
      }
      for (int i = 0; i < m; ++i) r.outline[r.n++] = corners[i];
    }
    const dvec2 d = e == 0 ? da : db;  // where the ray c + λ·d leaves the box
    double lambda = kInfD;
    for (int k = 0; k < 2; ++k) {
      if (d[k] > 0.0) {
        precise const double l = (hi[k] - c[k]) / d[k];
        lambda = min(lambda, l);
      }
      if (d[k] < 0.0) {
        precise const double l = (lo[k] - c[k]) / d[k];
        lambda = min(lambda, l);
      }
    }
    precise const dvec2 x = c + lambda * d;
    r.outline[r.n++] = x;
  }
  precise double area2 = 0.0;
  for (int i = 0; i + 1 < r.n; ++i)
    area2 += s * cross2(r.outline[i] - c, r.outline[i + 1] - c);
  precise const double minus = (r.tri2 > 0.0 ? 0.5 : -0.5) * (area2 - abs(r.tri2));
  r.minus_triangle = minus;
  return r;
}

/// coverage.cpp square_sector_minus_triangle.
double square_sector_minus_triangle(dvec2 a, dvec2 b) {
  return box_sector(dvec2(0.0), dvec2(1.0), a, b).minus_triangle;
}

/// atan(t) for t ≥ 0 in double: t > 1 through π/2 − atan(1/t), then two half-angle reductions
/// (atan t = 2 atan(t / (1 + √(1 + t²)))) to |u| ≤ tan(π/16) ≈ 0.2, where 12 terms of the Taylor
/// series leave an error below 1e-17: within a few ulps of std::atan.
double atan_nonnegative(double t) {
  const bool inverted = t > 1.0;
  precise double u = inverted ? 1.0 / t : t;
  for (int i = 0; i < 2; ++i) {
    precise const double h = u / (1.0 + sqrt(1.0 + u * u));
    u = h;
  }
  precise const double u2 = u * u;
  precise double series = 0.0;
  for (int k = 11; k >= 0; --k) series = 1.0 / double(2 * k + 1) - u2 * series;
  precise const double angle = 4.0 * u * series;
  const double half_pi = 1.57079632679489661923lf;
  precise const double result = inverted ? half_pi - angle : angle;
  return result;
}

/// atan2(y, x) in double, in (−π, π] (GLSL's atan has no double overload).
double atan2_double(double y, double x) {
  const double pi = 3.14159265358979323846lf;
  if (x == 0.0) return y > 0.0 ? 0.5 * pi : (y < 0.0 ? -0.5 * pi : 0.0);
  const double a = atan_nonnegative(abs(y) / abs(x));
  precise const double folded = x > 0.0 ? a : pi - a;
  return y < 0.0 ? -folded : folded;
}

/// Signed angle of (a − c, b − c), c = (½, ½): coverage.cpp's std::atan2, to a few ulps.
double sector_angle(dvec2 a, dvec2 b) {
  precise const dvec2 da = a - dvec2(0.5), db = b - dvec2(0.5);
  const double cr = cross2(da, db);
  precise const double dt = da.x * db.x + da.y * db.y;
  return atan2_double(cr, dt);
}

/// coverage.cpp disk_sector_minus_triangle.
double disk_sector_minus_triangle(dvec2 a, dvec2 b) {
  precise const dvec2 da = a - dvec2(0.5), db = b - dvec2(0.5);
  const double cr = cross2(da, db);
  const double angle = sector_angle(a, b);
  precise const double r = 0.5 * (0.25 * angle - cr);
  return r;
}
