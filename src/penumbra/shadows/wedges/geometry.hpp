// One penumbra wedge per silhouette edge: a conservative volume holding every point whose view of
// the light the edge can cut [Assarsson 2003 III §3.1; Assarsson 2003 IV §4.1; Forest 2008 §3.1.1,
// App. 3.B]. The coverage per pixel is exact (wedges/coverage.hpp); the wedge only culls which
// pixels get it, so it must contain the exact region and should be tight.
//
// The exact region of an edge e = (e0, e1) and a light L is S = {x + t·(X − x) : x ∈ L, X ∈ e,
// t ≥ 1}. Two constructions (method option `construction`):
//  - `paper` (default) [Assarsson 2003 III §3.1, Assarsson 2003 IV §4.1]: the vertex farther from
//  the light centre
//    c is moved toward c until both are at the same distance (top edge e0', e1). Rectangular
//    lights (Assarsson 2003 IV §4.1, the tighter wedge): front and back planes through the top
//    edge, tangent to the rectangle (touching its corners); the sides are the faces of the two end
//    pyramids (apex at a top-edge endpoint, the rectangle reflected through it) that face away
//    from the other endpoint ("the two leftmost and two rightmost triangles"). Round lights (disk,
//    sphere) use their bounding sphere (c, R) (Assarsson 2003 III §3.1): front and back planes
//    through the top edge tangent to the sphere; the right (left) plane through e0' (e1) contains
//    the direction ⟂ to both the top edge and c − e0' (c − e1) and is turned about it until it
//    touches the sphere, the other endpoint inside.
//  - `hull`: the tightest polyhedral volume: conv{e0, e1} + cone{e_i − x_k} (x_k the light hull
//    points: rectangle corners, a disk's bounding square, a sphere's bounding cube), cut by the
//    planes through the real edge tangent to the hull and the end-pyramid faces at the real
//    endpoints facing away from the other endpoint.
// Both extrude to infinity away from the light (Forest 2008 App. 3.B): no far cap.
//
// Why every plane is conservative (one lemma for all of them). Let f(y) = n·y − d with f ≤ 0 on
// the whole light and f ≥ 0 at both top-edge endpoints. The moved vertex is e0' = c + s·(e0 − c),
// 0 < s ≤ 1, so f(e0') = (1 − s)·f(c) + s·f(e0) with f(c) ≤ 0 (c is in the light's hull) gives
// f(e0) ≥ f(e0') / s ≥ 0: every original edge point X has f(X) ≥ 0. Then every point of S,
// y = X + (t − 1)·(X − x), has f(y) = f(X) + (t − 1)·(f(X) − f(x)) ≥ 0. Front/back planes contain
// the top edge (f = 0 there) and are tangent to the light (f ≤ 0 on it); side planes and pyramid
// faces pass through one top-edge endpoint with the light behind (f ≤ 0) and keep the other
// endpoint in front (f ≥ 0): each satisfies the lemma. build_wedge checks the lemma numerically
// for every plane it keeps and drops a plane that fails it.
//
// Fallbacks (conservative, only slower; counted in `degenerate`): a tangent plane that does not
// exist is dropped — the front/back planes when the light's hull wraps around the top edge's line
// (or its bounding sphere meets that line), a round light's side plane when the sphere contains the
// vertex or the other endpoint cannot be kept inside. A top edge of zero length (an edge pointing
// at the light centre, Assarsson 2003 III fig. 4b "a single cone") gets the pyramid faces of the
// light hull at that point. An edge that crosses a one-sided light (rectangle or disk) inside the
// light is clipped to the emitting side first (Assarsson 2003 IV §4.1, "If an edge intersects the
// light source"): the wedge then also gets the light's plane, and for an edge touching the light
// that half-space is all that remains (Assarsson 2003 IV: "all wedge planes are coplanar").
// Receivers strictly behind a one-sided light (which it does not light) may then miss that edge's
// coverage; edges that cross the light's plane outside the light need no clip (the lemma holds on
// both sides).
//
// The wedge is split by the hard-shadow quad (the plane through the light centre and the edge)
// into its inner and outer halves; the pass-2 sign follows from the projected geometry
// (wedges/coverage.hpp), so the split needs no separate test.
#pragma once

#include <cstdint>
#include <vector>

#include "penumbra/core/math.hpp"

namespace penumbra {

enum class WedgeConstruction : uint8_t { paper, hull };

/// What the wedge construction needs to know about a light.
struct WedgeLight {
  /// Points whose convex hull holds every emitting point from any receiver (rectangle corners, a
  /// disk's bounding square, a sphere's bounding cube), with `centre` inside.
  std::vector<DVec3> hull;
  DVec3 centre{0.0};  // the light centre (hard-shadow point, silhouettes)
  /// `paper` against the bounding sphere (centre, radius): disks and spheres (Assarsson 2003 III
  /// §3.1).
  bool round = false;
  double radius = 0.0;
  /// A planar light emitting to one side (rect, disk, not two-sided): edges crossing the light are
  /// clipped to the emitting side [Assarsson 2003 IV §4.1]. The light is the parallelogram corner +
  /// [0,1]·u
  /// + [0,1]·v (a disk: its inscribed circle, `radius`), emitting toward `normal` (unit).
  bool one_sided = false;
  bool disk = false;
  DVec3 normal{0.0}, corner{0.0}, edge_u{0.0}, edge_v{0.0};
};

struct WedgePlane {
  DVec3 n{0.0};
  double d = 0.0;  // inside iff dot(n, x) ≥ d − tolerance
};

inline constexpr int kMaxWedgePlanes = 16;

struct Wedge {
  int plane_count = 0;     // 0..kMaxWedgePlanes
  double tolerance = 0.0;  // absolute slack of the plane tests (world units)
  WedgePlane planes[kMaxWedgePlanes];
  DVec3 e0{0.0}, e1{0.0};  // the silhouette edge, directed from → to (multiplicity > 0)
  /// The generators of its screen bound (wedges/screen.hpp): the top edge (`paper`) or the edge
  /// (`hull`), after the clip to a one-sided light's emitting side.
  DVec3 top0{0.0}, top1{0.0};
  double weight = 0.0;      // multiplicity / layers of its mesh (see wedges/wedges.hpp)
  bool degenerate = false;  // a plane of the construction was missing (see the fallbacks above)

  bool contains(const DVec3& x) const {
    for (int i = 0; i < plane_count; ++i)
      if (glm::dot(planes[i].n, x) < planes[i].d - tolerance) return false;
    return true;
  }
  /// False only if no point of the box [lo, hi] is inside (some plane misses the whole box); an
  /// empty box (lo > hi) holds nothing.
  bool may_hold_box(const DVec3& lo, const DVec3& hi) const {
    if (!(lo.x <= hi.x && lo.y <= hi.y && lo.z <= hi.z)) return false;
    const DVec3 mid = 0.5 * (lo + hi), half = 0.5 * (hi - lo);
    for (int i = 0; i < plane_count; ++i)
      if (glm::dot(planes[i].n, mid) + glm::dot(glm::abs(planes[i].n), half) <
          planes[i].d - tolerance)
        return false;
    return true;
  }
};

/// Builds the wedge of edge e0 → e1. `scale` sets the test tolerance (≈ 1e-9 × scene size).
Wedge build_wedge(const DVec3& e0, const DVec3& e1, double weight, const WedgeLight& light,
                  WedgeConstruction construction, double scale);

}  // namespace penumbra
