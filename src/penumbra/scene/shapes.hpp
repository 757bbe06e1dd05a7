// Procedural meshes for the built-in scenes (no files needed).
#pragma once

#include "penumbra/scene/mesh.hpp"

namespace penumbra {

/// A rectangle centred at `center` spanned by full edge vectors (two triangles, uv over [0,1]²,
/// facing cross(edge_u, edge_v)).
Mesh make_quad(const Vec3& center, const Vec3& edge_u, const Vec3& edge_v);
/// A closed axis-aligned box (12 triangles, outward facing, shared vertices: 2-manifold).
Mesh make_box(const Vec3& center, const Vec3& half_extent);
/// A closed UV sphere with `rings` (>= 2) latitude bands and `segments` (>= 3) longitude slices
/// (2-manifold); smaller counts are raised to those minimums.
Mesh make_sphere(const Vec3& center, float radius, int rings, int segments);
/// A closed torus around the vertical axis through `center`: tube radius `minor_radius` swept
/// along the circle of radius `major_radius` in the plane y = center.y, `major_segments` (>= 3)
/// by `minor_segments` (>= 3) quads (2-manifold); smaller counts are raised to 3.
Mesh make_torus(const Vec3& center, float major_radius, float minor_radius, int major_segments,
                int minor_segments);
/// A thin open tube of triangular cross-section from `a` to `b` (a twig, a stem): three long quads
/// (six triangles, no end caps) whose corners lie `radius` from the axis, turned by `phase`
/// radians about it. `a` and `b` must differ.
Mesh make_open_prism(const Vec3& a, const Vec3& b, float radius, float phase = 0.0f);

}  // namespace penumbra
