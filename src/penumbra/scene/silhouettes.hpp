// Possible silhouette edges of a mesh w.r.t. a light point [Assarsson 2003 V; Forest 2008
// §2.2.1] and w.r.t. a whole area light [Forest 2008 §4.1.4], and their split into closed loops
// [Assarsson 2003 V, l.1796: the possible silhouette can always be split into closed loops].
//
// The robust rule for any mesh (closed, open, non-manifold, inconsistently oriented): signed edge
// multiplicity. Every valid face f has a side s_f ∈ {+1, −1, 0}: which side of its plane the light
// point lies on. Face f traverses edge e with sign o_{f,e} = ±1 (MeshEdges). The multiplicity of e
// is
//     m(e) = Σ_f s_f · o_{f,e}
// i.e. each face, turned to face the light, contributes its three edges. m(e) is the coefficient
// of e in the boundary of the chain Σ_f s_f·f, so at every vertex the signed multiplicities
// balance (∂∂ = 0) and the silhouette is a sum of closed loops. Consequences:
//   - closed, consistently oriented mesh: interior edges m = 0, one-front/one-back edges m = ±2
//     (the front face's and the back face's shadow volumes both have a side there);
//   - boundary edge of an open mesh: m = ±1 — it is always a silhouette and extrudes;
//   - non-manifold / inconsistent edges: whatever the sum gives; the shadow-volume count stays the
//     sum of the per-triangle volumes, i.e. the number of triangles a segment crosses.
// An edge is a silhouette iff m(e) ≠ 0; it is directed so that m > 0 (from → to).
#pragma once

#include <cstdint>
#include <vector>

#include "penumbra/scene/edges.hpp"
#include "penumbra/scene/light.hpp"

namespace penumbra {

/// Side of face f's plane the point lies on: +1 the side its normal cross(p1−p0, p2−p0) points to
/// ("front-facing"), −1 behind, 0 in the plane (or an invalid face). Double precision.
int face_side(const Mesh& mesh, const MeshEdges& edges, size_t face, const DVec3& point);
std::vector<int8_t> face_sides(const Mesh& mesh, const MeshEdges& edges, const Vec3& point);

struct SilhouetteEdge {
  uint32_t edge = 0;          // index into MeshEdges::edges
  uint32_t from = 0, to = 0;  // welded vertex indices, directed so that multiplicity > 0
  int32_t multiplicity = 0;   // |m(e)| ≥ 1
};

/// Silhouette edges (m ≠ 0) for per-face sides (face_sides), in edge order.
std::vector<SilhouetteEdge> silhouette_from_sides(const MeshEdges& edges,
                                                  const std::vector<int8_t>& sides);
/// Possible silhouette w.r.t. one light point.
std::vector<SilhouetteEdge> point_silhouette(const Mesh& mesh, const MeshEdges& edges,
                                             const Vec3& point);

/// Lowest and highest value of the affine function dot(n, x) − d over the light's points (the
/// whole rectangle, disk or sphere; a point light's centre).
void light_range(const Light& light, const DVec3& n, double d, double& lo, double& hi);

/// Possible silhouette edges w.r.t. the whole light (point, rect, disk, sphere) [Forest 2008
/// §4.1.4]: e is kept iff m(e) ≠ 0 for some point of the light. m can change over the light only
/// where an adjacent face's plane cuts the light, so e is kept iff m(e) ≠ 0 at the light centre or
/// some adjacent face plane has light points on both sides (closed or touching). For a manifold
/// edge this is exactly "some light point sees one face from the front and the other from the
/// back", up to the degenerate case of a light containing the edge's line. Returns edge indices,
/// sorted. Always a superset of point_silhouette(light.center).
std::vector<uint32_t> light_silhouette_edges(const Mesh& mesh, const MeshEdges& edges,
                                             const Light& light);

/// Splits a silhouette into closed loops: an Eulerian decomposition of the directed multigraph
/// with |m| / g copies of each edge, g = gcd of all multiplicities (so a closed mesh, m = ±2
/// everywhere, gives each loop once). Each loop lists indices into `silhouette` such that the
/// `to` of one is the `from` of the next and the last closes on the first. Deterministic.
std::vector<std::vector<uint32_t>> silhouette_loops(const std::vector<SilhouetteEdge>& silhouette);

}  // namespace penumbra
