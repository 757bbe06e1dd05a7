// `wedges` pass 2 [Assarsson 2003 III §3.2, IV §4.2, §5.1; Forest 2008 Algorithm 3]: per active
// pixel, the wedges [first, first + chunk) of its tile's bin that hold it, each edge projected
// from the pixel and clipped to the light, its signed coverage — area(square ∩ sector) −
// area(triangle) (coverage.cpp box_sector), the disk's sector minus triangle, or for a textured
// light the emission of that region per channel (wedge_emission.glsl) — added in bin order, in
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
const uint kLast = 2u, kFirst = 4u;

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
  uint na, first, chunk, mode;  // kFirst: starts the walk; kLast: closes the groups
  int em_w, em_h;
} pc;

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
      const dvec3 f = dvec3(area);
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
