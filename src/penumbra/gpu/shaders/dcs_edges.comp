#version 460
// dcs step 2 [Forest 2008 Algorithm 7 lines 4–11]: per active pixel, the wedges [first,
// first + chunk) of its tile's bin: the edge's weight for this receiver, the wedge test, the edge
// projected from the pixel and clipped to the light, its covered region, and the signed step on
// the counters of the samples it covers. Also records, per pixel, whether any edge was covered
// and Σ |step| of the opaque class (the CPU's umbra early-out, dcs_finish.comp). Dispatched once
// per chunk of the bins: llvmpipe caps the loop iterations of one invocation at 65535.
#include "common.glsl"
#include "dcs.glsl"

layout(push_constant) uniform Push {
  Pixels pix;
  Wedges wedges;
  Edges edges;
  Faces faces;
  Uints bin_begin;    // per tile, + 1
  Uints bin_entries;  // wedge indices
  Vec2s samples;      // sorted by band (dcs_counters.hpp SampleSet)
  Ints band_begin;    // k + 1
  Ints counters;
  Ints state;  // per pixel: any covered edge, Σ |step| of class 0
  uint na, n, k, first, chunk;
  uint sample_stride, band_stride;  // 0, or n and k + 1: each pixel's own samples
} pc;

/// multiplicity_for: the edge's weight for receiver p.
int weight(Edge e, dvec3 p) {
  if (e.face_count == 0u) return e.centre_multiplicity;
  int m = 0;
  for (uint f = e.face_begin; f < e.face_begin + e.face_count; ++f) {
    precise const double s = dot3(pc.faces.v[f].n, p) - pc.faces.v[f].d;
    m -= (int(s > 0.0) - int(s < 0.0)) * pc.faces.v[f].sign_;
  }
  return m;
}

bool contains(uint w, dvec3 p) {
  const int count = pc.wedges.v[w].plane_count;
  const double tol = pc.wedges.v[w].tolerance;
  for (int i = 0; i < count; ++i) {
    const dvec4 plane = pc.wedges.v[w].planes[i];
    precise const double lhs = dot3(plane.xyz, p);
    precise const double rhs = plane.w - tol;
    if (lhs < rhs) return false;
  }
  return true;
}

void main() {
  const uint a = global_id();
  if (a >= pc.na) return;
  const uint flags = pc.pix.v[a].flags;
  if ((flags & kValid) == 0u) return;  // in the light's plane: the centre count
  const uint tile = pc.pix.v[a].tile;
  const uint b1 = pc.bin_begin.v[tile + 1u];
  const uint from = pc.bin_begin.v[tile] + pc.first;
  if (from >= b1) return;
  const uint to = min(b1, from + pc.chunk);
  const dvec3 p = pc.pix.v[a].p;
  const dvec3 to_u = pc.pix.v[a].to_u, to_v = pc.pix.v[a].to_v, to_w = pc.pix.v[a].to_w;
  const int tau = (flags & kTauNeg) != 0u ? -1 : 1;
  int covered = 0, abs0 = 0;
  for (uint j = from; j < to; ++j) {
    const uint w = pc.bin_entries.v[j];
    const Edge e = pc.edges.v[pc.wedges.v[w].edge];
    const int m = weight(e, p);
    if (m == 0) continue;
    if (!contains(w, p)) continue;
    // LightProjection::homogeneous of the edge's ends, then the clip (PixelLight::clip).
    precise const dvec3 d0 = pc.wedges.v[w].e0 - p, d1 = pc.wedges.v[w].e1 - p;
    const dvec3 A = dvec3(dot3(d0, to_u), dot3(d0, to_v), dot3(d0, to_w));
    const dvec3 B = dvec3(dot3(d1, to_u), dot3(d1, to_v), dot3(d1, to_w));
    dvec2 ua, ub;
    if (!clip_square(A, B, ua, ub)) continue;
    if ((flags & kRound) != 0u && !clip_disk(ua, ub)) continue;
    Region r;
    int turn;
    if (!covered_region(ua, ub, r, turn)) continue;
    const int delta = -tau * m * turn;
    ++covered;
    if (e.layer_class == 0u) abs0 += abs(delta);
    int first, last;
    band_range(pc.band_begin, a * pc.band_stride, int(pc.k), r.v_lo, r.v_hi, first, last);
    const uint base = e.layer_class * pc.n, own = a * pc.sample_stride;
    for (int s = first; s < last; ++s)
      if (covers(r, pc.samples.v[own + uint(s)]))
        pc.counters.v[(base + uint(s)) * pc.na + a] += delta;
  }
  if (covered > 0) {
    pc.state.v[2u * a] = 1;
    pc.state.v[2u * a + 1u] += abs0;
  }
}
