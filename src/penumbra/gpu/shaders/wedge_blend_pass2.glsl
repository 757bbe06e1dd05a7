// `wedge_blend` per pixel [Forest 2008 Algorithms 4–6, eq. 3.1, §3.3.3]: the CPU pass of
// shadows/wedges/wedge_blend.cpp, operation for operation in double. Per caster group (the group
// hard counts and the tile bin's wedges, both in group order, merged as
// wedge_pass::for_each_group does) an SV-buffer of four light parts — occlusion per channel,
// bounding rectangle, outer- and inner-edge maxima, the inner edges' angle — is built from the
// outer half-wedges, then the inner ones, each edge clipped to every part it reaches; it is
// blended into the pixel's V-buffer by the effective overlapped area heuristic. With TEXTURED
// (wedge_blend_pass2_textured.comp) every share is the emitted power per channel
// (wedge_blend.cpp LightMeasure: wedge_emission.glsl), else the area (wedge_blend_pass2.comp). The
// angles come from wedge_coverage.glsl's double atan2 (GLSL has none), within a few ulps of the
// CPU's. The walk goes in steps (open a group, one bin entry of one pass, close the group) while the
// estimated loop iterations spent stay below `budget`; the V-buffer, the open SV-buffer and the
// cursors stay in `state` between dispatches (the first dispatch starts them, kStore keeps them),
// and a pixel whose walk is done writes its occlusion per channel (Σ part share × V part).
#include "common.glsl"
#include "dcs.glsl"
#include "wedge_coverage.glsl"
#ifdef TEXTURED
#include "wedge_emission.glsl"
#else
layout(buffer_reference, scalar) buffer DVec3s { dvec3 v[]; };
#endif

layout(buffer_reference, scalar) buffer Doubles { double v[]; };

/// wedge_blend.cpp Rect, in part-local coordinates s = |u − ½|, t = |v − ½|.
struct Rect {
  double s0, t0, s1, t1;
};

/// One light part of the SV-buffer (wedge_blend.cpp SvPart).
struct SvPart {
  dvec3 occ;
  Rect rect;
  double outer_s, outer_t, inner_s, inner_t, inner_angle;
};

/// Per active pixel between dispatches: the V-buffer (per part its occlusion per channel and
/// rectangle), the open group's SV-buffer, the next count entry, the open (or next) group's bin
/// entries [bi, bj), the next entry of the open pass, and the phase (kNoGroup, kOuter, kInner).
struct State {
  dvec3 v_occ[4];
  Rect v_rect[4];
  SvPart sv[4];
  uint ci, bi, bj, j, phase, pad;
};
layout(buffer_reference, scalar) buffer States { State v[]; };
const uint kNoGroup = 0u, kOuter = 1u, kInner = 2u;
const uint kFirst = 1u << 30, kStore = 1u << 31;

layout(push_constant) uniform Push {
  WedgePixels pix;
  Wedges wedges;
  Doubles weight;     // per wedge: multiplicity / layers
  Uints wedge_group;  // per wedge: its caster group
  Uints bin_begin;
  Uints bin_entries;
  Uints run_end;      // per bin entry: the end of its group's run in the bin
  Uints count_begin;  // per pixel: its group counts [count_begin[i], count_begin[i + 1])
  Uints count_group;
  Floats count_value;
  States state;
  DVec3s occ;      // per active pixel, written when its walk is done
  DVec3s part;     // the light's share in each part (LightMeasure::part)
  DVec3s density;  // a textured light's normalised emission per texel
  uint na;
  uint budget;  // loop iterations: a dispatch takes steps while it has spent less
  uint costs;   // an entry's (16 bits) and a group's (14 bits) estimated iterations, kFirst, kStore
  uint em_size;  // the texture's width and height, 16 bits each
} pc;

const double kPiD = 3.14159265358979323846lf;

Rect empty_rect() { return Rect(kInfD, kInfD, -kInfD, -kInfD); }
bool is_empty(Rect r) { return !(r.s1 > r.s0 && r.t1 > r.t0); }
double rect_area(Rect r) {
  precise const double a = (r.s1 - r.s0) * (r.t1 - r.t0);
  return is_empty(r) ? 0.0 : a;
}
void add_point(inout Rect r, double s, double t) {
  r.s0 = min(r.s0, s);
  r.s1 = max(r.s1, s);
  r.t0 = min(r.t0, t);
  r.t1 = max(r.t1, t);
}
void add_rect(inout Rect r, Rect o) {
  if (is_empty(o)) return;
  add_point(r, o.s0, o.t0);
  add_point(r, o.s1, o.t1);
}
void add_uv(inout Rect r, dvec2 p) {
  precise const double s = abs(p.x - 0.5), t = abs(p.y - 0.5);
  add_point(r, s, t);
}

dvec2 part_lo(int q) { return dvec2((q & 1) != 0 ? 0.5 : 0.0, (q & 2) != 0 ? 0.5 : 0.0); }

/// wedge_blend.cpp clip_to_part.
bool clip_to_part(int q, inout dvec2 a, inout dvec2 b) {
  const dvec2 lo = part_lo(q), hi = lo + dvec2(0.5);
  double t0 = 0.0, t1 = 1.0;
  precise const dvec2 d = b - a;
  precise const double p[4] = double[4](-d.x, d.x, -d.y, d.y);
  precise const double r[4] = double[4](a.x - lo.x, hi.x - a.x, a.y - lo.y, hi.y - a.y);
  for (int k = 0; k < 4; ++k) {
    if (p[k] == 0.0) {
      if (r[k] < 0.0) return false;
      continue;
    }
    precise const double t = r[k] / p[k];
    if (p[k] < 0.0)
      t0 = max(t0, t);
    else
      t1 = min(t1, t);
  }
  if (!(t0 < t1)) return false;
  precise const dvec2 na = a + t0 * d, nb = a + t1 * d;
  a = clamp(na, lo, hi);
  b = clamp(nb, lo, hi);
  return true;
}

/// wedge_blend.cpp part_sector: the sector in part q's box, and the part-local rectangle of a, b
/// and its outline; false when (c, a, b) has no area.
bool part_sector(int q, dvec2 a, dvec2 b, out double area, out Rect rect) {
  const BoxSector sector = box_sector(part_lo(q), part_lo(q) + dvec2(0.5), a, b);
  area = sector.minus_triangle;
  rect = empty_rect();
  if (sector.tri2 == 0.0) return false;
  add_uv(rect, a);
  add_uv(rect, b);
  for (int i = 0; i < sector.n; ++i) add_uv(rect, sector.outline[i]);
  return true;
}


/// The pixel, seen once.
dvec3 P, TO_U, TO_V, TO_W;
double TAU, INV_AREA, LIGHT_UV_AREA;
bool ROUND;
dvec3 PART[4];  // LightMeasure::part

/// −τ · weight · area / |light uv| (PixelLight::occlusion).
double occlusion(uint w, double area) {
  precise const double o = -TAU * pc.weight.v[w] * area * INV_AREA;
  return o;
}

/// LightMeasure::rect: the light's share in the part-local rectangle r of part q.
dvec3 measure_rect(int q, Rect r) {
  if (is_empty(r)) return dvec3(0.0);
#ifdef TEXTURED
  precise const double u0 = (q & 1) != 0 ? 0.5 + r.s0 : 0.5 - r.s1;
  precise const double u1 = (q & 1) != 0 ? 0.5 + r.s1 : 0.5 - r.s0;
  precise const double v0 = (q & 2) != 0 ? 0.5 + r.t0 : 0.5 - r.t1;
  precise const double v1 = (q & 2) != 0 ? 0.5 + r.t1 : 0.5 - r.t0;
  return emission_in_box(dvec2(u0, v0), dvec2(u1, v1));
#else
  precise const double share = rect_area(r) / LIGHT_UV_AREA;
  return dvec3(share);
#endif
}

/// The pixel's light-clipped edge of wedge w, and its sector-minus-triangle; false if none.
bool covered_edge(uint w, out dvec2 ua, out dvec2 ub, out double area) {
  area = 0.0;
  ua = dvec2(0.0), ub = dvec2(0.0);
  if (!wedge_contains(pc.wedges, w, P)) return false;
  precise const dvec3 d0 = pc.wedges.v[w].e0 - P, d1 = pc.wedges.v[w].e1 - P;
  const dvec3 A = dvec3(dot3(d0, TO_U), dot3(d0, TO_V), dot3(d0, TO_W));
  const dvec3 B = dvec3(dot3(d1, TO_U), dot3(d1, TO_V), dot3(d1, TO_W));
  if (!clip_square(A, B, ua, ub)) return false;
  if (ROUND && !clip_disk(ua, ub)) return false;
  area = ROUND ? disk_sector_minus_triangle(ua, ub) : square_sector_minus_triangle(ua, ub);
  return area != 0.0;
}

/// Algorithm 5 lines 7–15 for one edge in every part it reaches.
void add_edge(inout SvPart sv[4], uint w, dvec2 ea, dvec2 eb, bool outer) {
  const bool u_half[2] = bool[2](min(ea.x, eb.x) <= 0.5, max(ea.x, eb.x) >= 0.5);
  const bool v_half[2] = bool[2](min(ea.y, eb.y) <= 0.5, max(ea.y, eb.y) >= 0.5);
  for (int q = 0; q < 4; ++q) {
    if (!u_half[q & 1] || !v_half[(q >> 1) & 1]) continue;
    dvec2 a = ea, b = eb;
    if (!clip_to_part(q, a, b)) continue;
    double sector_area;
    Rect sector_rect;
    if (!part_sector(q, a, b, sector_area, sector_rect)) continue;
    const double area = ROUND ? disk_sector_minus_triangle(a, b) : sector_area;
    if (area == 0.0) continue;
#ifdef TEXTURED
    const dvec3 f = weighted_sector_minus_triangle(a, b);
    const dvec3 share = dvec3(occlusion(w, f.x), occlusion(w, f.y), occlusion(w, f.z));
#else
    const dvec3 share = dvec3(occlusion(w, area));
#endif
    for (int k = 0; k < 3; ++k) {
      if (PART[q][k] > 0.0) {
        precise const double d = share[k] / PART[q][k];
        sv[q].occ[k] += d;
      }
    }
    precise const double as = abs(a.x - 0.5), at = abs(a.y - 0.5);
    precise const double bs = abs(b.x - 0.5), bt = abs(b.y - 0.5);
    if (outer) {
      add_rect(sv[q].rect, sector_rect);
      sv[q].outer_s = max(sv[q].outer_s, max(as, bs));
      sv[q].outer_t = max(sv[q].outer_t, max(at, bt));
    } else {
      sv[q].inner_s = max(sv[q].inner_s, max(as, bs));
      sv[q].inner_t = max(sv[q].inner_t, max(at, bt));
      sv[q].inner_angle += abs(sector_angle(a, b));
    }
  }
}

bool any_positive(dvec3 v) { return v.x > 0.0 || v.y > 0.0 || v.z > 0.0; }

/// Algorithm 6 with eq. 3.1 for part q (wedge_blend.cpp blend_part), per channel.
void blend_part(int q, SvPart s, inout dvec3 v_occ, inout Rect v_rect) {
  if (!any_positive(s.occ)) return;
  if (!any_positive(v_occ)) {
    v_occ = s.occ;
    v_rect = s.rect;
    return;
  }
  precise dvec3 blended = s.occ + v_occ;
  const Rect inter = Rect(max(s.rect.s0, v_rect.s0), max(s.rect.t0, v_rect.t0),
                          min(s.rect.s1, v_rect.s1), min(s.rect.t1, v_rect.t1));
  if (rect_area(inter) > 0.0) {
    const dvec3 bs = measure_rect(q, s.rect), bv = measure_rect(q, v_rect);
    const dvec3 beta = measure_rect(q, inter);
    const dvec3 w = PART[q];
    for (int c = 0; c < 3; ++c) {
      if (!(w[c] > 0.0)) continue;
      precise const double rs = s.occ[c] * w[c] / bs[c], rv = v_occ[c] * w[c] / bv[c];
      const double ratio_s = bs[c] > 0.0 ? min(1.0, rs) : 1.0;
      const double ratio_v = bv[c] > 0.0 ? min(1.0, rv) : 1.0;
      precise const double eps = ratio_v * ratio_s * beta[c] / w[c];
      blended[c] -= eps;
    }
  }
  v_occ = clamp(blended, dvec3(0.0), dvec3(1.0));
  add_rect(v_rect, s.rect);
}

/// Opens the next group (wedge_pass::for_each_group): its hard count initialises the SV-buffer
/// (Algorithm 4 line 4), its wedges are the run of bin entries from bi.
void open_group(inout State st, uint ce, uint be) {
  uint grp = st.ci < ce ? pc.count_group.v[st.ci] : 0xffffffffu;
  if (st.bi < be) grp = min(grp, pc.wedge_group.v[pc.bin_entries.v[st.bi]]);
  double count = 0.0;
  if (st.ci < ce && pc.count_group.v[st.ci] == grp) count = double(pc.count_value.v[st.ci++]);
  st.bj = st.bi < be && pc.wedge_group.v[pc.bin_entries.v[st.bi]] == grp ? pc.run_end.v[st.bi]
                                                                         : st.bi;
  for (int q = 0; q < 4; ++q)
    st.sv[q] = SvPart(dvec3(count), count > 0.0 ? Rect(0.0, 0.0, 0.5, 0.5) : empty_rect(), 0.0,
                      0.0, 0.0, 0.0, 0.0);
  st.j = st.bi;
  st.phase = kOuter;
}

/// Algorithm 5 for bin entry j in the open pass: outer half-wedges first, then inner (§3.3.3).
void add_entry(inout State st, uint j) {
  const uint w = pc.bin_entries.v[j];
  dvec2 ea, eb;
  double area;
  if (!covered_edge(w, ea, eb, area)) return;
  const bool outer = occlusion(w, area) > 0.0;
  if (outer != (st.phase == kOuter)) return;
  add_edge(st.sv, w, ea, eb, outer);
}

/// Closes the open group: decrease_brect, the clamp, and the blend into the V-buffer
/// (Algorithm 4 line 7).
void close_group(inout State st) {
  for (int q = 0; q < 4; ++q) {
    SvPart p = st.sv[q];
    if (p.inner_angle >= 0.5 * kPiD * (1.0 - 1e-9lf) && !is_empty(p.rect)) {
      p.rect.s1 = max(p.rect.s0, min(p.rect.s1, max(p.inner_s, p.outer_s)));
      p.rect.t1 = max(p.rect.t0, min(p.rect.t1, max(p.inner_t, p.outer_t)));
    }
    p.occ = clamp(p.occ, dvec3(0.0), dvec3(1.0));
    blend_part(q, p, st.v_occ[q], st.v_rect[q]);
  }
  st.bi = st.bj;
  st.phase = kNoGroup;
}

void main() {
  const uint a = global_id();
  if (a >= pc.na) return;
  const uint flags = pc.pix.v[a].flags;
  const uint pixel = pc.pix.v[a].pixel;
  P = pc.pix.v[a].p;
  TO_U = pc.pix.v[a].to_u, TO_V = pc.pix.v[a].to_v, TO_W = pc.pix.v[a].to_w;
  TAU = (flags & kTauNeg) != 0u ? -1.0 : 1.0;
  INV_AREA = pc.pix.v[a].inv_area;
  ROUND = (flags & kRound) != 0u;
  LIGHT_UV_AREA = ROUND ? kPiD * 0.25 : 1.0;
  for (int q = 0; q < 4; ++q) PART[q] = pc.part.v[q];
#ifdef TEXTURED
  EM = pc.density;
  EM_W = int(pc.em_size & 0xffffu), EM_H = int(pc.em_size >> 16);
#endif
  const bool valid = (flags & kValid) != 0u;

  State st;
  if ((pc.costs & kFirst) != 0u) {  // the walk's start: an empty V-buffer, the first entries
    for (int q = 0; q < 4; ++q) {
      st.v_occ[q] = dvec3(0.0);
      st.v_rect[q] = empty_rect();
    }
    st.ci = pc.count_begin.v[pixel];
    st.bi = pc.bin_begin.v[pc.pix.v[a].tile];
    st.bj = st.bi, st.j = st.bi, st.phase = kNoGroup, st.pad = 0u;
  } else {
    st = pc.state.v[a];
  }
  const uint ce = pc.count_begin.v[pixel + 1u];
  const uint tile = pc.pix.v[a].tile;
  const uint be = valid ? pc.bin_begin.v[tile + 1u] : st.bi;
  // One step per iteration (open a group, one entry of a pass, close the group), so a dispatch
  // can stop anywhere and the next one resume.
  bool done = false;
  for (uint spent = 0u; spent < pc.budget;) {
    if (st.phase == kNoGroup) {
      if (!(st.ci < ce || st.bi < be)) {
        done = true;
        break;
      }
      open_group(st, ce, be);
      spent += (pc.costs >> 16) & 0x3fffu;
    } else if (st.j < st.bj) {
      add_entry(st, st.j++);
      spent += pc.costs & 0xffffu;
    } else if (st.phase == kOuter) {
      st.phase = kInner;
      st.j = st.bi;
    } else {
      close_group(st);
      spent += (pc.costs >> 16) & 0x3fffu;
    }
  }
  if ((pc.costs & kStore) != 0u) pc.state.v[a] = st;
  if (!done) return;
  precise dvec3 occ = dvec3(0.0);
  for (int q = 0; q < 4; ++q) occ += PART[q] * st.v_occ[q];
  pc.occ.v[a] = occ;
}
