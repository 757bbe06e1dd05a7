// Per-sample depth-complexity counters of one receiver, and the update of the samples an edge's
// projection covers [Forest 2008 §4.1.2–4.1.3, Algorithm 7, §4.4.3].
//
// Covered samples. Seen from p, the walk in light uv from the centre c to a sample s crosses the
// clipped projected edge a → b iff s lies in the sector from c spanned by a and b and beyond the
// line ab: three half-planes, each an affine function of s (`CoveredRegion`). When c lies on the
// segment itself (p in the plane of the edge and the light centre, Forest §4.4.3: "the light
// center passes through the line"), the sector degenerates to the half-plane beyond the line; we
// take the side the walk from c + εd reaches (a fixed direction d, a symbolic perturbation), so
// the covered set is still a half-plane of samples and is never dropped the way an area of zero
// would be.
//
// Counters. The paper packs several unsigned counters in one word because a GPU render target has
// four channels, and updates them with one add (§4.1.3, fig. 4.2); on a CPU the same idea is a SIMD
// register of small signed lanes. The samples are stored as float arrays (u, v) and the counters
// as int16 (or int32 when a pixel's bound could overflow 16 bits: the adaptive precision of
// §4.2.3, chosen per pixel from its initial count plus the sum of its edges' weights); one edge
// updates all samples with branch-free compare-and-add loops that the compiler vectorises (16
// floats and 32 int16 counters per AVX-512 register on the build machine). Signed lanes need no
// outer-before-inner ordering (§4.1.4's two batches exist only for unsigned counters).
#pragma once

#include <cstdint>

#include "penumbra/core/math.hpp"

namespace penumbra::dcs {

/// covered(s) ⟺ h1(s) ≥ 0 ∧ h2(s) ≥ 0 ∧ h3(s) < 0 with h_i(s) = a_i·u + b_i·v + c_i.
struct CoveredRegion {
  float a[3], b[3], c[3];
};

/// The samples the walk from the light centre (0.5, 0.5) to them crosses the clipped uv segment
/// a → b; `turn` gets the side (+1: (c, a, b) counter-clockwise, −1 clockwise) the count changes
/// with. False when no sample can be crossed (c on the segment's line but off the segment).
bool covered_region(const DVec2& a, const DVec2& b, CoveredRegion& region, int& turn);

/// counters[s] += delta for every covered sample; returns how many were covered.
template <class Counter>
inline int apply_region(Counter* __restrict counters, const float* __restrict u,
                        const float* __restrict v, int n, const CoveredRegion& r, int delta) {
  const float a0 = r.a[0], b0 = r.b[0], c0 = r.c[0];
  const float a1 = r.a[1], b1 = r.b[1], c1 = r.c[1];
  const float a2 = r.a[2], b2 = r.b[2], c2 = r.c[2];
  const Counter d = static_cast<Counter>(delta);
  int covered = 0;
  for (int s = 0; s < n; ++s) {
    const float h0 = a0 * u[s] + b0 * v[s] + c0;
    const float h1 = a1 * u[s] + b1 * v[s] + c1;
    const float h2 = a2 * u[s] + b2 * v[s] + c2;
    const bool in = (h0 >= 0.0f) & (h1 >= 0.0f) & (h2 < 0.0f);
    counters[s] += in ? d : Counter(0);
    covered += in;
  }
  return covered;
}

}  // namespace penumbra::dcs
