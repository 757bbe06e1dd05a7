// The per-pixel coverage of one silhouette edge, the heart of pass 2 of the penumbra-wedge
// algorithm [Assarsson 2003 III §3.2; Assarsson 2003 IV §4.2; Forest 2008 §3.1.2, Algorithm 3].
//
// The edge is projected from the receiver point p onto the light's plane (homogeneous light
// coordinates of exact/projection.hpp: U, V, W linear in the world point), clipped to the part that
// can block light (0 < W ≤ 1: between p and the light plane) and to the light (0 ≤ U, V ≤ W), then
// divided to light uv. Its coverage is the area of the light between the projected segment a→b
// and the light's boundary, inside the angular sector the segment spans as seen from the light
// centre c = (0.5, 0.5): "sector area minus triangle" (c, a, b) [Assarsson 2003 IV §4.2.2 for
// rectangles, §4.2.1 for spheres and disks]. Why this is the right quantity: along every ray from c
// the crossing count of the projected silhouette changes by the edge's multiplicity exactly where
// the ray crosses the edge, so integrating over the light,
//     (light-averaged count) = count(c) + Σ_edges ± m_e · sector_minus_triangle_e / light area,
// which is the paper's "hard shadow from the centre, plus inner, minus outer wedge halves".
#pragma once

#include <cmath>
#include <vector>

#include "penumbra/core/math.hpp"
#include "penumbra/scene/texture.hpp"

namespace penumbra {

/// Clips the homogeneous light-space segment A→B (x = U, y = V, z = W of exact/projection.hpp) to
/// kMinW ≤ W ≤ 1, 0 ≤ U ≤ W, 0 ≤ V ≤ W and divides: a, b in light uv [0,1]². False if nothing
/// remains. The direction a→b is that of A→B.
bool clip_edge_to_light_square(const DVec3& A, const DVec3& B, DVec2& a, DVec2& b);

/// Clips the uv segment a→b (inside the uv square) to the inscribed disk (centre (0.5, 0.5),
/// radius 0.5). False if nothing remains.
bool clip_edge_to_light_disk(DVec2& a, DVec2& b);

/// The sector from c = (0.5, 0.5) spanned by a and b (angle below π) within a box [lo, hi] that
/// holds c (inside or on its border): a star polygon from c, so no clipping — its outline is the
/// exit of the ray c → a through the box's border, the box corners strictly between the rays in
/// angular order, then the exit of the ray c → b. Shared by square_sector_minus_triangle and
/// wedge_blend's per-part areas and rectangles [Forest 2008 §3.2.1].
struct BoxSector {
  double tri2 = 0.0;   // cross(a − c, b − c): twice the signed area of (c, a, b); 0: no sector
  double area2 = 0.0;  // twice the (unsigned) area of box ∩ sector
  int n = 0;           // outline points without c: exit(a), corners, exit(b)
  DVec2 outline[4];
  /// area(box ∩ sector) − area(c, a, b), signed by (c, a, b)'s turn.
  double minus_triangle() const {
    return tri2 == 0.0 ? 0.0 : (tri2 > 0.0 ? 0.5 : -0.5) * (area2 - std::abs(tri2));
  }
};
BoxSector box_sector(const DVec2& lo, const DVec2& hi, const DVec2& a, const DVec2& b);

/// Signed area, in uv units, of the region of the uv square between the segment a→b (inside the
/// square) and the square's boundary, inside the sector from c = (0.5, 0.5) spanned by a and b:
/// area(square ∩ sector) − area(c, a, b) [Assarsson 2003 IV §4.2.2]. Positive when (c, a, b) turns
/// counter-clockwise, negative when clockwise, 0 when c is on the segment's line.
double square_sector_minus_triangle(const DVec2& a, const DVec2& b);

/// The same for the inscribed disk: (r²·angle(a, b) − cross(a − c, b − c)) / 2 with r = 0.5
/// [Assarsson 2003 IV §4.2.1].
double disk_sector_minus_triangle(const DVec2& a, const DVec2& b);

/// The 4D coverage texture of Assarsson 2003 III §3.3 for a uniform rectangular light: the coverage
/// f(x1, y1, x2, y2) = |square_sector_minus_triangle(a, b)| of the light by the projected hard
/// shadow quad of a clipped edge a = (x1, y1) → b = (x2, y2) (Assarsson 2003 III fig. 8),
/// precomputed with exact clipping for both endpoints on an n × n grid over the light (n⁴ floats)
/// and looked up per pixel. In light uv it is the same for every rectangle, so one table serves
/// every light and sub-light. The sign (outer or inner half) is not in the table: it is taken
/// exactly from the orientation of (c, a, b), as Assarsson 2003 III §3.2.2 takes it from the
/// half-space of the quad.
/// **Deviation:** the paper puts the n × n positions at texel centres; we put them at
/// i / (n − 1), i = 0..n−1, so that endpoints on the light's border (most clipped endpoints) are
/// interpolated, not extrapolated. The unsigned f is continuous: where the segment passes through
/// c, a line through the centre of the square halves it, so both sides give ½.
class CoverageTexture {
 public:
  enum class Lookup {
    bilinear,      // nearest grid point for a, bilinear in b (Assarsson 2003 III §3.3, "bilinear
                   // filtering")
    quadrilinear,  // bilinear in a of bilinear in b (16 taps, Assarsson 2003 III §3.3)
  };
  explicit CoverageTexture(int n);
  int n() const { return n_; }
  /// The n⁴ entries, [((ya · n + xa) · n + yb) · n + xb] (the Vulkan pass looks them up too).
  const std::vector<float>& entries() const { return table_; }
  /// Unsigned coverage from the table, in uv units.
  double unsigned_coverage(const DVec2& a, const DVec2& b, Lookup lookup) const;
  /// Signed like square_sector_minus_triangle (> 0 when (c, a, b) turns counter-clockwise).
  double sector_minus_triangle(const DVec2& a, const DVec2& b, Lookup lookup) const;

 private:
  double bilinear_b(size_t sub, const DVec2& b) const;
  int n_ = 0;
  std::vector<float> table_;  // [((ya · n + xa) · n + yb) · n + xb]
};

/// A per-pair bound on |texture − exact| derived in docs/methods/wedges.md ("Coverage texture"):
/// with h = 1/(n − 1), R = √2/2 and L(d) = 1/(4d) + R/2 the Lipschitz bound of f in one endpoint
/// at distance d from c, bilinear: h·(L_a/√2 + √2·L_b); quadrilinear: √2·h·(L_a + L_b), with
/// each L evaluated at d − (its endpoint's displacement). Infinite when an endpoint is too close
/// to c.
double coverage_texture_bound(const DVec2& a, const DVec2& b, int n,
                              CoverageTexture::Lookup lookup);

/// The emission of a textured rectangular light over light uv (nearest texel, as exact and the
/// sampling methods read it: texel (tx, ty) covers [tx/w, (tx+1)/w] × [ty/h, (ty+1)/h]), as a
/// per-channel density normalised so that each emitting channel integrates to 1 over the square.
struct LightEmission {
  int width = 0, height = 0;
  std::vector<DVec3> density;  // per texel, row-major; 0 in a channel the light does not emit
  DVec3 total{0.0};            // Σ texel RGB × radiance × texel area (uv units), per channel
  DVec3 max_density{0.0};      // max over texels of `density`, per channel
  LightEmission(const Texture& texture, const Vec3& radiance);
};

/// The emission-weighted square_sector_minus_triangle: per channel, the normalised emission of
/// the same region (fraction of the channel's total), with the same sign. 0 when c is on the
/// segment's line (like square_sector_minus_triangle).
DVec3 weighted_sector_minus_triangle(const LightEmission& emission, const DVec2& a, const DVec2& b);

/// The normalised emission (per channel, fraction of the channel's total) of the uv box [lo, hi]
/// inside the light square: exact over the texels.
DVec3 emission_in_box(const LightEmission& emission, const DVec2& lo, const DVec2& hi);

/// The RGB coverage texture for a textured rectangular light (Assarsson 2003 III §3.3
/// "also serves textured lights"): per endpoint pair on the same n × n grid as CoverageTexture, the
/// unsigned |weighted_sector_minus_triangle| per channel, computed exactly by clipping the region
/// against every texel. Unlike the uniform table, the unsigned value is discontinuous where the
/// segment passes through c (the region jumps from the half-square on one side to the other's),
/// so a pair through c stores the limit of the counter-clockwise side (the half right of a→b) and
/// the lookup continues every tap across that line to the lookup's own side (v → 1 − v, the
/// complement; docs/methods/wedges.md "Textured lights").
class CoverageTextureRGB {
 public:
  CoverageTextureRGB(int n, const LightEmission& emission);
  int n() const { return n_; }
  /// Signed like weighted_sector_minus_triangle.
  DVec3 sector_minus_triangle(const DVec2& a, const DVec2& b, CoverageTexture::Lookup lookup) const;

 private:
  DVec3 tap(int xa, int ya, int xb, int yb, int sign) const;
  int n_ = 0;
  std::vector<float> table_;  // 3 floats per entry, entries ordered as CoverageTexture's
};

/// coverage_texture_bound for the RGB table of one channel with maximum normalised density
/// rho_max: the same derivation with L_w(d) = rho_max · (1/(4d) + √2/2) (the region's symmetric
/// difference, not its area, is what moves; docs/methods/wedges.md "Textured lights").
double coverage_texture_rgb_bound(const DVec2& a, const DVec2& b, int n,
                                  CoverageTexture::Lookup lookup, double rho_max);

}  // namespace penumbra
