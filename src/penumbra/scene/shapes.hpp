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

}  // namespace penumbra
