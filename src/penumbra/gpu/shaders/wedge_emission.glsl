// A textured rectangular light's emission over light uv, shared by `wedges` and `wedge_blend` on
// Vulkan: shadows/wedges/coverage.cpp weigh_polygon, weighted_region,
// weighted_sector_minus_triangle and emission_in_box, operation for operation in double
// (`precise`), so the per-channel coverage of an edge is the CPU's [Assarsson 2003 III §3.3: a
// textured light weighs the covered region by its emission]. The normalised per-texel densities
// (LightEmission::density, nearest texel) are read from EM (EM_W × EM_H, row-major), which the
// shader sets in main(). Needs wedge_coverage.glsl.

layout(buffer_reference, scalar) buffer DVec3s { dvec3 v[]; };

DVec3s EM;
int EM_W, EM_H;

/// The value of clip plane `mode` at p: 0 p.x − k.x, 1 k.x − p.x, 2 p.y − k.y, 3 k.y − p.y; 4 the
/// far side of the line a→b = (k, k + d) for sign s: −s · cross(d, p − a).
double clip_value(int mode, dvec2 p, dvec2 k, dvec2 d, double s) {
  precise double f;
  if (mode == 0)
    f = p.x - k.x;
  else if (mode == 1)
    f = k.x - p.x;
  else if (mode == 2)
    f = p.y - k.y;
  else if (mode == 3)
    f = k.y - p.y;
  else
    f = -s * cross2(d, p - k);
  return f;
}

/// coverage.cpp clip_poly: the part of the convex polygon where clip_value ≥ 0 (≤ 16 vertices).
int clip_poly(inout dvec2 poly[16], int n, int mode, dvec2 k, dvec2 d, double s) {
  dvec2 tmp[16];
  int m = 0;
  for (int i = 0; i < n && m < 15; ++i) {
    const dvec2 p = poly[i], q = poly[(i + 1) % n];
    const double fp = clip_value(mode, p, k, d, s), fq = clip_value(mode, q, k, d, s);
    if (fp >= 0.0) tmp[m++] = p;
    if ((fp >= 0.0) != (fq >= 0.0)) {
      precise const dvec2 x = p + (fp / (fp - fq)) * (q - p);
      tmp[m++] = x;
    }
  }
  for (int i = 0; i < m; ++i) poly[i] = tmp[i];
  return m;
}

/// coverage.cpp poly_area.
double poly_area(dvec2 poly[16], int n) {
  precise double a2 = 0.0;
  for (int i = 0; i < n; ++i) a2 += cross2(poly[i], poly[(i + 1) % n]);
  precise const double a = 0.5 * abs(a2);
  return a;
}

/// coverage.cpp weigh_polygon: Σ over texels of density × area(poly ∩ texel).
dvec3 weigh_polygon(dvec2 poly[16], int n) {
  precise dvec3 sum = dvec3(0.0);
  if (n < 3) return sum;
  dvec2 lo = dvec2(1.0), hi = dvec2(0.0);
  for (int i = 0; i < n; ++i) {
    lo = min(lo, poly[i]);
    hi = max(hi, poly[i]);
  }
  const double w = double(EM_W), h = double(EM_H);
  const int x0 = clamp(int(floor(lo.x * w)), 0, EM_W - 1);
  const int x1 = clamp(int(ceil(hi.x * w)) - 1, x0, EM_W - 1);
  const int y0 = clamp(int(floor(lo.y * h)), 0, EM_H - 1);
  const int y1 = clamp(int(ceil(hi.y * h)) - 1, y0, EM_H - 1);
  if (x0 == x1 && y0 == y1) {
    precise const dvec3 r = EM.v[y0 * EM_W + x0] * poly_area(poly, n);
    return r;
  }
  // One flat loop over the texel box (llvmpipe counts the iterations of nested loops).
  const int bw = x1 - x0 + 1, texels = bw * (y1 - y0 + 1);
  for (int t = 0; t < texels; ++t) {
    const int tx = x0 + t % bw, ty = y0 + t / bw;
    precise const double u0 = double(tx) / w, u1 = double(tx + 1) / w;
    precise const double v0 = double(ty) / h, v1 = double(ty + 1) / h;
    dvec2 q[16] = poly;
    int m = n;
    // The outermost texels reach to the square's border (the polygon is inside it anyway).
    if (tx > 0) m = clip_poly(q, m, 0, dvec2(u0, 0.0), dvec2(0.0), 0.0);
    if (m >= 3 && tx < EM_W - 1) m = clip_poly(q, m, 1, dvec2(u1, 0.0), dvec2(0.0), 0.0);
    if (m >= 3 && ty > 0) m = clip_poly(q, m, 2, dvec2(0.0, v0), dvec2(0.0), 0.0);
    if (m >= 3 && ty < EM_H - 1) m = clip_poly(q, m, 3, dvec2(0.0, v1), dvec2(0.0), 0.0);
    if (m >= 3) sum += EM.v[ty * EM_W + tx] * poly_area(q, m);
  }
  return sum;
}

/// coverage.cpp through_line: c on the line of a→b up to rounding (relative 1e-12).
bool through_line(dvec2 da, dvec2 db, double tri2) {
  precise const double la = sqrt(da.x * da.x + da.y * da.y);
  precise const double lb = sqrt(db.x * db.x + db.y * db.y);
  precise const double bound = 1e-12lf * la * lb;
  return abs(tri2) <= bound;
}

/// coverage.cpp weighted_region: the weighted region of branch `sign` between a→b and the square's
/// border, inside the sector from c (the branch's half square when c is on the segment).
dvec3 weighted_region(dvec2 a, dvec2 b, double sign) {
  const dvec2 c = dvec2(0.5);
  precise const dvec2 da = a - c, db = b - c;
  const double tri2 = cross2(da, db);
  dvec2 poly[16];
  int n = 0;
  precise const double dab = da.x * db.x + da.y * db.y;
  if (through_line(da, db, tri2)) {
    if (!(dab < 0.0)) return dvec3(0.0);
    poly[0] = dvec2(0.0);
    poly[1] = dvec2(1.0, 0.0);
    poly[2] = dvec2(1.0);
    poly[3] = dvec2(0.0, 1.0);
    n = 4;
  } else {
    const BoxSector sector = box_sector(dvec2(0.0), dvec2(1.0), a, b);
    if (sector.tri2 == 0.0) return dvec3(0.0);
    poly[n++] = c;
    for (int i = 0; i < sector.n; ++i)
      poly[n++] = sector.outline[sector.tri2 > 0.0 ? i : sector.n - 1 - i];
  }
  if (n < 3) return dvec3(0.0);
  precise const dvec2 d = b - a;
  n = clip_poly(poly, n, 4, a, d, sign);
  return weigh_polygon(poly, n);
}

/// coverage.cpp weighted_sector_minus_triangle: per channel the normalised emission of the
/// region square_sector_minus_triangle measures, with its sign.
dvec3 weighted_sector_minus_triangle(dvec2 a, dvec2 b) {
  precise const dvec2 da = a - dvec2(0.5), db = b - dvec2(0.5);
  const double tri2 = cross2(da, db);
  if (tri2 == 0.0) return dvec3(0.0);
  const double s = tri2 > 0.0 ? 1.0 : -1.0;
  precise const dvec3 r = s * weighted_region(a, b, s);
  return r;
}

/// coverage.cpp emission_in_box: the normalised emission of the uv box [lo, hi], the product of
/// the overlaps per texel.
dvec3 emission_in_box(dvec2 lo_in, dvec2 hi_in) {
  const dvec2 lo = clamp(lo_in, dvec2(0.0), dvec2(1.0)), hi = clamp(hi_in, dvec2(0.0), dvec2(1.0));
  precise dvec3 sum = dvec3(0.0);
  if (!(hi.x > lo.x && hi.y > lo.y)) return sum;
  const double w = double(EM_W), h = double(EM_H);
  const int x0 = clamp(int(floor(lo.x * w)), 0, EM_W - 1);
  const int x1 = clamp(int(ceil(hi.x * w)) - 1, x0, EM_W - 1);
  const int y0 = clamp(int(floor(lo.y * h)), 0, EM_H - 1);
  const int y1 = clamp(int(ceil(hi.y * h)) - 1, y0, EM_H - 1);
  const int bw = x1 - x0 + 1, texels = bw * (y1 - y0 + 1);
  for (int t = 0; t < texels; ++t) {
    const int tx = x0 + t % bw, ty = y0 + t / bw;
    precise const double tv0 = double(ty) / h, tv1 = double(ty + 1) / h;
    precise const double tu0 = double(tx) / w, tu1 = double(tx + 1) / w;
    const double v0 = ty > 0 ? max(lo.y, tv0) : lo.y;
    const double v1 = ty < EM_H - 1 ? min(hi.y, tv1) : hi.y;
    const double u0 = tx > 0 ? max(lo.x, tu0) : lo.x;
    const double u1 = tx < EM_W - 1 ? min(hi.x, tu1) : hi.x;
    if (!(v1 > v0) || !(u1 > u0)) continue;
    precise const double area = (u1 - u0) * (v1 - v0);
    sum += EM.v[ty * EM_W + tx] * area;
  }
  return sum;
}
