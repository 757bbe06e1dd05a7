// Per-sample depth-complexity counters of one receiver, and the update of the samples an edge's
// projection covers [Forest 2008 §4.1.2–4.1.3, Algorithm 7, §4.4.3].
//
// Covered samples. Seen from p, the walk in light uv from the centre c to a sample s crosses the
// clipped projected edge a → b iff s lies in the sector from c spanned by a and b and beyond the
// line ab: three half-planes, each an affine function of s (`CoveredRegion`). When c lies on the
// segment itself (p in the plane of the edge and the light centre, Forest 2008 §4.4.3: "the light
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

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <span>
#include <vector>

#include "penumbra/core/math.hpp"

namespace penumbra::dcs {

/// covered(s) ⟺ h1(s) ⪰ 0 ∧ h2(s) ⪰ 0 ∧ h3(s) < 0 with h_i(s) = a_i·u + b_i·v + c_i; every
/// covered sample has v_lo ≤ v ≤ v_hi. The two rays from c are where neighbouring silhouette edges'
/// sectors meet (a shared vertex projects to one uv, so their h are exact negatives or equal): a
/// sample on such a ray (h = 0 in float) must fall in exactly one of them, or its count is off by
/// the edge's multiplicity. It is taken as if turned by an infinitesimal angle counter-clockwise
/// about c (a symbolic perturbation, the same for every edge): `closed[k]` says whether h_k = 0
/// then counts as inside.
struct CoveredRegion {
  float a[3], b[3], c[3];
  bool closed[2] = {true, true};
  double v_lo = 0.0, v_hi = 1.0;
};

/// The samples the walk from the light centre (0.5, 0.5) to them crosses the clipped uv segment
/// a → b; `turn` gets the side (+1: (c, a, b) counter-clockwise, −1 clockwise) the count changes
/// with. False when no sample can be crossed (c on the segment's line but off the segment).
bool covered_region(const DVec2& a, const DVec2& b, CoveredRegion& region, int& turn);

/// The samples of one pixel sorted into k bands of v (band j: j/k ≤ v < (j+1)/k), so that an
/// edge tests only the bands its covered region spans — most projected edges cover a few samples
/// near the light's border. `index` maps back to LightSamples order (masks).
struct SampleSet {
  int k = 0;
  std::vector<float> u, v;
  std::vector<Vec2> uv;
  std::vector<uint8_t> emit;
  std::vector<uint16_t> index;
  std::vector<int> band_begin;  // k + 1 entries
  /// Sorts `light_uv` (k² samples) by band; emit(uv) tells the emitting ones.
  template <class Emits>
  void assign(std::span<const Vec2> light_uv, int bands, Emits&& emits) {
    k = bands;
    const size_t n = light_uv.size();
    u.resize(n), v.resize(n), uv.resize(n), emit.resize(n), index.resize(n);
    band_begin.assign(k + 2, 0);
    auto band = [&](const Vec2& p) {
      return std::clamp(static_cast<int>(p.y * static_cast<float>(k)), 0, k - 1);
    };
    for (const Vec2& p : light_uv) ++band_begin[band(p) + 2];
    for (int j = 2; j < k + 2; ++j) band_begin[j] += band_begin[j - 1];
    for (size_t s = 0; s < n; ++s) {
      const int at = band_begin[band(light_uv[s]) + 1]++;
      u[at] = light_uv[s].x, v[at] = light_uv[s].y, uv[at] = light_uv[s];
      emit[at] = emits(light_uv[s]) ? 1 : 0;
      index[at] = static_cast<uint16_t>(s);
    }
    band_begin.pop_back();
  }
  /// The sample range [first, last) of the bands holding [v_lo, v_hi].
  void range(double v_lo, double v_hi, int& first, int& last) const {
    const double m = 1e-5;  // the float test may accept a sample a rounding error outside
    const int b0 = std::clamp(static_cast<int>(std::floor((v_lo - m) * k)), 0, k - 1);
    const int b1 = std::clamp(static_cast<int>(std::floor((v_hi + m) * k)), 0, k - 1);
    first = band_begin[b0];
    last = band_begin[b1 + 1];
  }
};

/// counters[s] += delta for every covered sample; returns how many were covered.
template <class Counter>
inline int apply_region(Counter* __restrict counters, const float* __restrict u,
                        const float* __restrict v, int n, const CoveredRegion& r, int delta) {
  const float a0 = r.a[0], b0 = r.b[0], c0 = r.c[0];
  const float a1 = r.a[1], b1 = r.b[1], c1 = r.c[1];
  const float a2 = r.a[2], b2 = r.b[2], c2 = r.c[2];
  const bool closed0 = r.closed[0], closed1 = r.closed[1];
  const Counter d = static_cast<Counter>(delta);
  int covered = 0;
  for (int s = 0; s < n; ++s) {
    const float h0 = a0 * u[s] + b0 * v[s] + c0;
    const float h1 = a1 * u[s] + b1 * v[s] + c1;
    const float h2 = a2 * u[s] + b2 * v[s] + c2;
    const bool in0 = (h0 > 0.0f) | ((h0 == 0.0f) & closed0);
    const bool in1 = (h1 > 0.0f) | ((h1 == 0.0f) & closed1);
    const bool in = in0 & in1 & (h2 < 0.0f);
    counters[s] += in ? d : Counter(0);
    covered += in;
  }
  return covered;
}

}  // namespace penumbra::dcs
