// Transmittance sampling of one S-triangle from one receiver point [Forest 2008 §5.1.4,
// eqs. 5.7–5.10, App. 5.A].
//
// The paper projects each light sample s onto the triangle's plane as seen from p: with M'
// (eq. 5.8, per triangle: world → the basis (e1, e2, n)) and W (eq. 5.9, per p: p as projective
// centre), s*_h = W·M'·s holds the homogeneous barycentrics of the point where the line from p
// through s meets the plane, and the sample is occluded when s*_h.x ≥ 0, s*_h.y ≥ 0 and
// s*_h.z − s*_h.x − s*_h.y ≥ 0. Here the light samples are given in light uv, s = C + u·U + v·V
// (LightFrame), so J = W·M' composed with that affine map is a 3 × 3 matrix from (u, v, 1): each
// row an affine function of the sample, 6 MUL + 6 ADD per sample instead of the 9 MUL + 6 ADD of
// the world-space form. Its z row is 1/λ, λ the segment parameter of the crossing (p at 0, s at
// 1), so the triangle lies strictly between p and s under the project's tie rule
// (shadows/method.hpp: λ ≤ kShadowSegmentEnd) iff s*_h.z ≥ 1/kShadowSegmentEnd — one more compare.
// For the samples that pass, β = s*_h.xy / s*_h.z (eq. 5.10's projection, on barycentrics) and the
// texel is the one raytrace reads for the same barycentrics: Mesh::uv_at's interpolation (the
// matrix S of eq. 5.5) and Texture::texel_index, alpha < kAlphaCutoff a hole.
//
// J is built in double per (pixel, triangle) and evaluated in float per sample: a sample whose
// answer the rounding can change lies within float precision of a triangle edge, of the tie
// band, or of a texel border (the ties of tests/support/mask_agreement.hpp).
#pragma once

#include <algorithm>
#include <cstdint>

#include "penumbra/scene/light.hpp"
#include "penumbra/shadows/exact/projection.hpp"
#include "penumbra/shadows/method.hpp"
#include "penumbra/shadows/wedges/stsv.hpp"

namespace penumbra::stsv {

/// J of one (pixel, S-triangle), rows x, y, z: h_r(u, v) = a[r]·u + b[r]·v + c[r].
struct Pair {
  float a[3], b[3], c[3];
  double v_lo = 0.0, v_hi = 1.0;  // light-v range of the samples it can block
};

/// Sets up J for receiver point p under light frame (C, U, V); `lp` (the frame's projection from
/// p, or null) bounds the samples by the triangle's projection. False when no sample can be
/// blocked: p in the triangle's plane, the triangle beyond the light, or its projection missing
/// the light's uv square.
inline bool make_pair(const STriangle& t, const DVec3& p, const DVec3& corner, const DVec3& edge_u,
                      const DVec3& edge_v, const LightProjection* lp, Pair& out) {
  if (lp) {
    // The triangle's projection from p onto the light: when every vertex lies on the light's
    // side of p (W > 0), it is the triangle of the projected vertices; a vertex beyond the light
    // (W > 1) blocks nothing of it.
    const DVec3 h[3] = {lp->homogeneous(t.v0), lp->homogeneous(t.v0 + t.e1),
                        lp->homogeneous(t.v0 + t.e2)};
    if (h[0].z > 1.0 && h[1].z > 1.0 && h[2].z > 1.0) return false;
    if (h[0].z > 0.0 && h[1].z > 0.0 && h[2].z > 0.0) {
      double u0 = kInfinity, u1 = -kInfinity, v0 = kInfinity, v1 = -kInfinity;
      for (const DVec3& x : h) {
        u0 = std::min(u0, x.x / x.z), u1 = std::max(u1, x.x / x.z);
        v0 = std::min(v0, x.y / x.z), v1 = std::max(v1, x.y / x.z);
      }
      const double m = 1e-6;  // float evaluation may accept a sample a rounding error outside
      if (u1 < -m || u0 > 1.0 + m || v1 < -m || v0 > 1.0 + m) return false;
      out.v_lo = v0, out.v_hi = v1;
    }
  }
  // M'·(v0 − p) = (a0, b0, e): e is p's distance to the plane in units of |n| (eq. 5.9's e).
  const DVec3 g0 = t.to_triangle * (t.v0 - p);
  if (!(g0.z != 0.0)) return false;  // p in the plane
  // W: h = (a − a0·c/e, b − b0·c/e, c/e) for M'·(s − p) = (a, b, c).
  auto row = [&](const DVec3& g, int r) {
    return static_cast<float>(r == 0   ? g.x - g0.x * g.z / g0.z
                              : r == 1 ? g.y - g0.y * g.z / g0.z
                                       : g.z / g0.z);
  };
  const DVec3 gu = t.to_triangle * edge_u, gv = t.to_triangle * edge_v,
              gc = t.to_triangle * (corner - p);
  for (int r = 0; r < 3; ++r) out.a[r] = row(gu, r), out.b[r] = row(gv, r), out.c[r] = row(gc, r);
  return true;
}

/// 1/λ of the segment end of the tie rule, as the float the z row is compared with.
inline const float kMinInverseT = static_cast<float>(1.0 / kShadowSegmentEnd);

/// For samples [0, n) (light uv in u[], v[]): blocked[s] = 1 when the segment from p to sample s
/// crosses an opaque texel of `t`, else 0. Returns the number of alpha lookups (samples whose
/// segment crosses the triangle). One branch-free loop the compiler vectorises, the texel fetch a
/// gather (wedges/stsv_lookup.cpp).
int blocked_samples(const Pair& pr, const STriangle& t, const float* __restrict u,
                    const float* __restrict v, int n, uint8_t* __restrict blocked);

}  // namespace penumbra::stsv
