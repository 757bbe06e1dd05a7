// Consistent winding and hole geometry of a triangle mesh, for the methods that count a closed
// mesh's light-facing faces only (the wedge methods, wedges/pass.hpp). Whether a mesh may be
// counted as a solid is a geometric question — is it orientable, and how large are its holes —
// not one of how many of its edges lie on a boundary: a finely tessellated open bowl has < 1 %
// boundary edges and a 50 % hole.
#pragma once

#include <cstddef>

#include "penumbra/scene/edges.hpp"

namespace penumbra {

struct Reorientation {
  size_t flipped = 0;         // faces whose winding was reversed
  size_t non_orientable = 0;  // connected components with no consistent winding (left as is)
  bool changed() const { return flipped > 0; }
};

/// Makes the winding of every orientable connected component consistent (breadth-first over the
/// edges with exactly two faces: across such an edge the two faces must traverse it in opposite
/// directions), keeping in each component the winding most of its faces already have (so one
/// flipped triangle is turned back, not the other n − 1). Components joined only through
/// non-manifold edges are oriented independently; a non-orientable component (a Möbius strip) is
/// left as it is. Returns the mesh with reversed triangles and what was changed.
Mesh reorient(const Mesh& mesh, const MeshEdges& edges, Reorientation* report = nullptr);

/// Hole geometry of a mesh: its boundary split into closed loops, each measured by the magnitude
/// of its vector area |½ Σ p_i × p_{i+1}| (the area of the smallest cap of a planar loop, a lower
/// bound of any surface spanning a non-planar one), against the mesh's surface area.
struct HoleGeometry {
  size_t loops = 0;
  double hole_area = 0.0;     // Σ over loops of |vector area|
  double surface_area = 0.0;  // Σ of valid face areas
  double fraction() const { return surface_area > 0.0 ? hole_area / surface_area : 0.0; }
};
HoleGeometry hole_geometry(const Mesh& mesh, const MeshEdges& edges);

}  // namespace penumbra

namespace penumbra {

/// Generalised winding number of the mesh around `point` (Σ of the faces' signed solid angles /
/// 4π, Van Oosterom–Strackee): ≈ ±1 inside a closed consistently oriented mesh, 0 outside.
double winding_number(const Mesh& mesh, const MeshEdges& edges, const DVec3& point);

/// True if `point` lies on a face of the mesh: in the face's plane (face_side = 0, the test every
/// shadow method shares) and inside the triangle or on its border.
bool point_on_surface(const Mesh& mesh, const MeshEdges& edges, const DVec3& point);

}  // namespace penumbra
