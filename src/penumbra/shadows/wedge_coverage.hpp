// The per-pixel coverage of one silhouette edge, the heart of pass 2 of the penumbra-wedge
// algorithm [seed 000 paper III §3.2; paper IV §4.2; Forest thesis §3.1.2, Algorithm 3].
//
// The edge is projected from the receiver point p onto the light's plane (homogeneous light
// coordinates of exact_projection.hpp: U, V, W linear in the world point), clipped to the part that
// can block light (0 < W ≤ 1: between p and the light plane) and to the light (0 ≤ U, V ≤ W), then
// divided to light uv. Its coverage is the area of the light between the projected segment a→b
// and the light's boundary, inside the angular sector the segment spans as seen from the light
// centre c = (0.5, 0.5): "sector area minus triangle" (c, a, b) [paper IV §4.2.2 for rectangles,
// §4.2.1 for spheres and disks]. Why this is the right quantity: along every ray from c the
// crossing count of the projected silhouette changes by the edge's multiplicity exactly where the
// ray crosses the edge, so integrating over the light,
//     (light-averaged count) = count(c) + Σ_edges ± m_e · sector_minus_triangle_e / light area,
// which is the paper's "hard shadow from the centre, plus inner, minus outer wedge halves".
#pragma once

#include "penumbra/core/math.hpp"

namespace penumbra {

/// Clips the homogeneous light-space segment A→B (x = U, y = V, z = W of exact_projection.hpp) to
/// kMinW ≤ W ≤ 1, 0 ≤ U ≤ W, 0 ≤ V ≤ W and divides: a, b in light uv [0,1]². False if nothing
/// remains. The direction a→b is that of A→B.
bool clip_edge_to_light_square(const DVec3& A, const DVec3& B, DVec2& a, DVec2& b);

/// Clips the uv segment a→b (inside the uv square) to the inscribed disk (centre (0.5, 0.5),
/// radius 0.5). False if nothing remains.
bool clip_edge_to_light_disk(DVec2& a, DVec2& b);

/// The box [lo, hi] (containing or touching c = (0.5, 0.5)) clipped to the sector from c spanned
/// by a and b (angle below π): writes the polygon (at most 8 vertices, counter-clockwise) to
/// `poly` and returns its vertex count (< 3: empty). 0 when c, a, b are collinear. Shared by
/// square_sector_minus_triangle and wedge_blend's per-part rectangles [Forest §3.2.1].
int clip_box_to_sector(const DVec2& lo, const DVec2& hi, const DVec2& a, const DVec2& b,
                       DVec2 poly[8]);

/// Signed area, in uv units, of the region of the uv square between the segment a→b (inside the
/// square) and the square's boundary, inside the sector from c = (0.5, 0.5) spanned by a and b:
/// area(square ∩ sector) − area(c, a, b) [paper IV §4.2.2]. Positive when (c, a, b) turns
/// counter-clockwise, negative when clockwise, 0 when c is on the segment's line.
double square_sector_minus_triangle(const DVec2& a, const DVec2& b);

/// The same for the inscribed disk: (r²·angle(a, b) − cross(a − c, b − c)) / 2 with r = 0.5
/// [paper IV §4.2.1].
double disk_sector_minus_triangle(const DVec2& a, const DVec2& b);

}  // namespace penumbra
