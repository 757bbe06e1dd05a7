// The unshadowed irradiance of an area light in closed form: no quadrature, no light samples.
//
// Every formula here evaluates the projected solid angle P = ∫_Ω max(0, n·ω) dω of the light's
// shape seen from the receiver point p with unit normal n, restricted to the hemisphere n·ω > 0
// ("clipped to the horizon"); a Lambertian emitter of radiance L then gives E = L·P (π × the
// point-to-area form factor). By Stokes' theorem P is a contour integral over the shape's outline,
//   P = ½ |∮ n · (x × dx) / |x|²|,   x = the outline point minus p,
// which is invariant under moving outline points along their rays from p. For a straight edge it
// is θ·(n·û), θ the angle the edge subtends and û the unit normal of the plane through p and the
// edge: Lambert's polygon formula (Lambert 1760; in graphics [Arvo 1994]). For a circle it is a
// ratio of two trigonometric polynomials of degree one, which integrates in closed form (below).
#pragma once

#include <cstdint>
#include <vector>

#include "penumbra/core/image.hpp"
#include "penumbra/core/math.hpp"
#include "penumbra/render/gbuffer.hpp"
#include "penumbra/scene/scene.hpp"

namespace penumbra {

/// P of the planar polygon corners[0..count) (any orientation, count ≤ 8), clipped to n·(x − p) >
/// 0.
double polygon_projected_solid_angle(const DVec3& p, const DVec3& n, const DVec3* corners,
                                     int count);

/// P of the disk centre + radius·(cos t·axis_u + sin t·axis_v) (orthonormal axes), clipped to the
/// hemisphere. Closed form: with q = centre − p, the contour integrand is
///   (A + B cos t + C sin t) / (D + E cos t + F sin t),
///   A = r² n·(u×v), B = r n·(q×v), C = −r n·(q×u), D = |q|² + r², E = 2r q·u, F = 2r q·v,
/// which after rotating t so that the denominator reads D + ρ cos τ integrates to arctangents and
/// a logarithm (rational_arc_integral in the .cpp, written to stay exact as ρ → 0). The arc below
/// the horizon is cut where n·x(t) = 0 and closed by the chord in the horizon plane.
double disk_projected_solid_angle(const DVec3& p, const DVec3& n, const DVec3& center,
                                  const DVec3& axis_u, const DVec3& axis_v, double radius);

/// A light's unshadowed irradiance at any receiver, exact for every light shape:
/// - rect: the parallelogram's P; one-sided lights give 0 behind their plane;
/// - disk: the disk formula;
/// - sphere: the disk formula on its silhouette disk from the receiver (light_frame), which spans
///   the same cone as the sphere, so this is the sphere's cap, horizon-clipped. Fully above the
///   horizon it equals π sin²α cos β (α the cap's half-angle, β its axis' angle to n);
/// - textured rect: Σ over texels of the texel's radiance × its polygon's P (the emission is
///   piecewise constant per texel: nearest lookup). A texture wider or taller than
///   kMaxIrradianceBlocksPerSide texels is summed over that many blocks per side instead, each
///   with the area-weighted mean of its texels: exact where a block is uniform, and the cost per
///   pixel stays bounded;
/// - point: radiance · max(0, cos θ) / r².
inline constexpr int kMaxIrradianceBlocksPerSide = 32;  // ≤ 2·33·32 edge terms per pixel
class LightIrradiance {
 public:
  LightIrradiance(const Scene& scene, const Light& light);

  /// E at receiver point `p` with unit normal `n`, linear RGB (radiance × P).
  Vec3 at(const Vec3& p, const Vec3& n) const;

  /// at(g.shadow_origin(i), g.shading_normal[i]) at every pixel i whose class in `classes` is
  /// kActive (receivers.hpp); other pixels of `out` (g's size) are left as they are. Rows in
  /// parallel. An untextured rectangle wholly above a receiver's horizon, the common case, is
  /// evaluated 8 receivers at a time with glibc's vector atan2 where the build has it: within a few
  /// double ulps of at(), so the float result is at() to within one float ulp (at() itself
  /// elsewhere).
  void fill(const GBuffer& g, const Image<uint8_t>& classes, Image<Vec3>& out) const;
  /// fill's work on row y alone (one thread): rows are independent, so any split of them among
  /// threads gives fill's image.
  void fill_row(const GBuffer& g, const Image<uint8_t>& classes, Image<Vec3>& out, int y) const;

  /// Texel blocks the textured sum runs over (0 × 0 for an untextured light).
  int blocks_u() const { return blocks_u_; }
  int blocks_v() const { return blocks_v_; }

 private:
  Vec3 textured_at(const DVec3& p, const DVec3& n, const LightFrame& f) const;
  /// fill's batched rectangle path for the receivers pixels[0..count) (count ≤ 8).
  void fill_rect_batch(const GBuffer& g, const size_t* pixels, int count, Image<Vec3>& out) const;

  const Light* light_;
  // An untextured rectangle's corners and emitting side, for fill's batches (as at() forms them).
  DVec3 rect_corners_[4];
  DVec3 rect_emit_{0.0};
  int blocks_u_ = 0;
  int blocks_v_ = 0;
  std::vector<DVec3> block_radiance_;  // row-major, row 0 at v = 0
};

}  // namespace penumbra
