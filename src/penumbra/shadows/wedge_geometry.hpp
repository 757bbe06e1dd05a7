// One penumbra wedge per silhouette edge: a conservative volume holding every point whose view of
// the light the edge can cut [seed 000 paper III §3.1; paper IV §4.1; Forest thesis §3.1.1,
// App. 3.B].
//
// The exact region of an edge e = (e0, e1) and a light L is S = {x + t·(X − x) : x ∈ L, X ∈ e,
// t ≥ 1}. Our wedge is the intersection of half-spaces each proven to contain S:
//  - front and back planes: through the edge's line, tangent to a convex hull of the light (the
//    light's corners; for round lights the bounding square's, for spheres the bounding cube's).
//    Around the line, S lies opposite the light, inside the dihedral angle between the two
//    tangent planes. This is paper IV §4.1's tighter wedge for rectangular lights applied to the
//    edge itself: we do NOT move the farther vertex toward the light centre (paper III §3.1),
//    because that wedge is not guaranteed to contain S and our coverage is exact only if every
//    pixel the edge affects is visited;
//  - left and right planes through e0 (e1): the light behind, the other endpoint in front
//    (paper III §3.1's side planes, chosen by a closed-form tilt; dropped when none exists);
//  - infinite extent away from the light (Forest App. 3.B): no far cap.
// When the light's hull wraps around the edge's line (an edge pointing into the light), the front
// and back planes do not exist and the wedge is only bounded by its side planes and its screen
// extent: still conservative, only slower.
//
// The wedge is split by the hard-shadow quad (the plane through the light centre and the edge)
// into its inner and outer halves; the pass-2 sign follows from the projected geometry
// (wedge_coverage.hpp), so the split needs no separate test.
#pragma once

#include <cstdint>
#include <vector>

#include "penumbra/core/math.hpp"

namespace penumbra {

struct WedgePlane {
  DVec3 n{0.0};
  double d = 0.0;  // inside iff dot(n, x) ≥ d − tolerance
};

struct Wedge {
  DVec3 e0{0.0}, e1{0.0};  // the silhouette edge, directed from → to (multiplicity > 0)
  double weight = 0.0;     // multiplicity / layers of its mesh (see wedges.hpp)
  int plane_count = 0;     // 0..4
  WedgePlane planes[4];
  double tolerance = 0.0;  // absolute slack of the plane tests (world units)

  bool contains(const DVec3& x) const {
    for (int i = 0; i < plane_count; ++i)
      if (glm::dot(planes[i].n, x) < planes[i].d - tolerance) return false;
    return true;
  }
};

/// Builds the wedge of edge e0 → e1 for a light whose every emitting point (from any receiver)
/// lies in the convex hull of `light_hull`, with `light_centre` inside it. `scale` sets the test
/// tolerance (≈ 1e-9 × scene size).
Wedge build_wedge(const DVec3& e0, const DVec3& e1, double weight,
                  const std::vector<DVec3>& light_hull, const DVec3& light_centre, double scale);

}  // namespace penumbra
