// `wedges` pass 2 [Assarsson 2003 III §3.2, IV §4.2, §5.1; Forest 2008 Algorithm 3]: per active
// pixel, the wedges [first, first + chunk) of its tile's bin that hold it, each edge projected
// from the pixel and clipped to the light, its signed coverage — area(square ∩ sector) −
// area(triangle) (coverage.cpp box_sector), the disk's sector minus triangle, or for a textured
// light the emission of that region per channel (wedge_emission.glsl), or with kTable the coverage
// texture's value for a rectangle (Assarsson 2003 III §3.3) — added in bin order, in
// double, to its caster group's sum, which starts from the group's hard count. Groups come in
// order from the count entries and the bin (wedge_pass::for_each_group); each group's clamped
// sum is folded into the pixel's total by the overlap approximation's max + ½ min (Assarsson 2003
// IV §5.1, eq. 1). Plain `wedges` is one group holding every wedge with the layered hard count, for
// which the fold is the clamp of the CPU's sum. The walk's state lives in `state` between chunks;
// the last chunk closes the groups and leaves the per-channel total there. Included by
// wedges_pass2.comp and, with TEXTURED defined, wedges_pass2_textured.comp (one shader with both
// ran the untextured pass 3–4× slower on lavapipe).
#include "common.glsl"
#include "dcs.glsl"
#include "wedge_coverage.glsl"
#ifdef TEXTURED
#include "wedge_emission.glsl"
#else
layout(buffer_reference, scalar) buffer DVec3s { dvec3 v[]; };
#endif

layout(buffer_reference, scalar) buffer Doubles { double v[]; };

/// Per active pixel: the open group's sum and the folded total per channel, the open group
/// (kNone: none) and the next count entry.
struct State {
  dvec3 sum, total;
  uint grp, ci;
};
layout(buffer_reference, scalar) buffer States { State v[]; };
const uint kNone = 0xffffffffu;
const uint kLast = 2u, kFirst = 4u, kTable = 8u, kQuadrilinear = 16u;

layout(push_constant) uniform Push {
  WedgePixels pix;
  Wedges wedges;
  Doubles weight;     // per wedge: multiplicity / layers
  Uints wedge_group;  // per wedge: its caster group
  Uints bin_begin;
  Uints bin_entries;
  Uints count_begin;  // per pixel: its group counts [count_begin[i], count_begin[i + 1])
  Uints count_group;
  Floats count_value;
  States state;
  DVec3s density;  // a textured light's normalised emission per texel
  Floats table;    // the coverage texture (kTable): table_n⁴ entries
  uint na, first, chunk, mode;  // kFirst: starts the walk; kLast: closes the groups; kTable...
  int em_w, em_h;
  uint table_n, pad;
} pc;

/// coverage.cpp cell: the grid cell and fraction of u on the nodes i / (n − 1).
void table_cell(double u, out uint i, out double t) {
  const int n = int(pc.table_n);
  precise const double f = clamp(u, 0.0, 1.0) * double(n - 1);
  const int c = min(int(f), n - 2);
  precise const double frac = f - double(c);
  i = uint(c);
  t = frac;
}

/// CoverageTexture::bilinear_b: bilinear in b within the table slice of a's node `sub`.
double table_bilinear_b(uint sub, dvec2 b) {
  uint ix, iy;
  double tx, ty;
  table_cell(b.x, ix, tx);
  table_cell(b.y, iy, ty);
  const uint m = pc.table_n;
  const uint k = sub * m * m + iy * m + ix;
  const double t0 = double(pc.table.v[k]), t1 = double(pc.table.v[k + 1u]);
  const double t2 = double(pc.table.v[k + m]), t3 = double(pc.table.v[k + m + 1u]);
  precise const double r0 = (1.0 - tx) * t0 + tx * t1, r1 = (1.0 - tx) * t2 + tx * t3;
  precise const double r = (1.0 - ty) * r0 + ty * r1;
  return r;
}

/// std::lround of clamp(u, 0, 1) · (n − 1): the nearest node (halves away from zero).
uint table_nearest(double u) {
  precise const double x = clamp(u, 0.0, 1.0) * double(int(pc.table_n) - 1);
  const double f = floor(x);
  precise const double frac = x - f;
  return uint(f) + (frac >= 0.5 ? 1u : 0u);
}

/// CoverageTexture::sector_minus_triangle [Assarsson 2003 III §3.3]: the table's unsigned
/// coverage, nearest in a and bilinear in b, or quadrilinear, signed by (c, a, b)'s turn.
double table_sector_minus_triangle(dvec2 a, dvec2 b) {
  precise const dvec2 da = a - dvec2(0.5), db = b - dvec2(0.5);
  const double tri2 = cross2(da, db);
  if (tri2 == 0.0) return 0.0;
  const uint m = pc.table_n;
  double f;
  if ((pc.mode & kQuadrilinear) == 0u) {
    f = table_bilinear_b(table_nearest(a.y) * m + table_nearest(a.x), b);
  } else {
    uint ix, iy;
    double tx, ty;
    table_cell(a.x, ix, tx);
    table_cell(a.y, iy, ty);
    const uint s = iy * m + ix;
    precise const double r0 =
        (1.0 - tx) * table_bilinear_b(s, b) + tx * table_bilinear_b(s + 1u, b);
    precise const double r1 =
        (1.0 - tx) * table_bilinear_b(s + m, b) + tx * table_bilinear_b(s + m + 1u, b);
    precise const double r = (1.0 - ty) * r0 + ty * r1;
    f = r;
  }
  precise const double signed_f = (tri2 > 0.0 ? 1.0 : -1.0) * f;
  return signed_f;
}

/// wedges.cpp overlap_combine per channel, of the open group's clamped sum.
void close_group(inout State s) {
  for (int k = 0; k < 3; ++k) {
    const double c = s.total[k], cg = clamp(s.sum[k], 0.0, 1.0);
    precise const double t = max(c, cg) + 0.5 * min(c, cg);
    s.total[k] = min(1.0, t);
  }
  s.grp = kNone;
}

/// Closes the count-only groups before group g (all of them for g = kNone).
void close_counts_before(inout State s, uint ce, uint g) {
  while (s.ci < ce && (g == kNone || pc.count_group.v[s.ci] < g)) {
    s.sum = dvec3(double(pc.count_value.v[s.ci++]));
    close_group(s);
  }
}

void main() {
  const uint a = global_id();
  if (a >= pc.na) return;
  const uint flags = pc.pix.v[a].flags;
  const uint pixel = pc.pix.v[a].pixel;
  const uint ce = pc.count_begin.v[pixel + 1u];
#ifdef TEXTURED
  EM = pc.density;
  EM_W = pc.em_w, EM_H = pc.em_h;
#endif
  State s;
  if ((pc.mode & kFirst) != 0u)
    s = State(dvec3(0.0), dvec3(0.0), kNone, pc.count_begin.v[pixel]);
  else
    s = pc.state.v[a];
  if ((flags & kValid) != 0u) {
    const uint tile = pc.pix.v[a].tile;
    const uint b1 = pc.bin_begin.v[tile + 1u];
    const uint from = pc.bin_begin.v[tile] + pc.first;
    const uint to = min(b1, from + pc.chunk);
    const dvec3 p = pc.pix.v[a].p;
    const dvec3 to_u = pc.pix.v[a].to_u, to_v = pc.pix.v[a].to_v, to_w = pc.pix.v[a].to_w;
    const double tau = (flags & kTauNeg) != 0u ? -1.0 : 1.0;
    const double inv_area = pc.pix.v[a].inv_area;
    for (uint j = from; j < to; ++j) {
      const uint w = pc.bin_entries.v[j];
      const uint g = pc.wedge_group.v[w];
      if (s.grp != g) {  // a new group: close the open one and the count-only ones before it
        if (s.grp != kNone) close_group(s);
        close_counts_before(s, ce, g);
        s.grp = g;
        s.sum = dvec3(0.0);
        if (s.ci < ce && pc.count_group.v[s.ci] == g) s.sum = dvec3(double(pc.count_value.v[s.ci++]));
      }
      if (!wedge_contains(pc.wedges, w, p)) continue;
      precise const dvec3 d0 = pc.wedges.v[w].e0 - p, d1 = pc.wedges.v[w].e1 - p;
      const dvec3 A = dvec3(dot3(d0, to_u), dot3(d0, to_v), dot3(d0, to_w));
      const dvec3 B = dvec3(dot3(d1, to_u), dot3(d1, to_v), dot3(d1, to_w));
      dvec2 ua, ub;
      if (!clip_square(A, B, ua, ub)) continue;
      const bool round = (flags & kRound) != 0u;
      if (round && !clip_disk(ua, ub)) continue;
      const double area =
          round ? disk_sector_minus_triangle(ua, ub) : square_sector_minus_triangle(ua, ub);
      if (area == 0.0) continue;
      // PixelLight::occlusion: −τ · weight · area / |light uv|, per channel.
#ifdef TEXTURED
      const dvec3 f = weighted_sector_minus_triangle(ua, ub);
#else
      const dvec3 f =
          dvec3((pc.mode & kTable) != 0u && !round ? table_sector_minus_triangle(ua, ub) : area);
#endif
      for (int k = 0; k < 3; ++k) {
        precise const double occlusion = -tau * pc.weight.v[w] * f[k] * inv_area;
        s.sum[k] += occlusion;
      }
    }
  }
  if ((pc.mode & kLast) != 0u) {
    if (s.grp != kNone) close_group(s);
    close_counts_before(s, ce, kNone);
  }
  pc.state.v[a] = s;
}
