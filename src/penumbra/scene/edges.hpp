// Edge adjacency of a triangle mesh: every undirected edge knows its faces (and the direction each
// face traverses it), and is classified as closed 2-manifold, boundary (open), non-manifold or
// inconsistently oriented. The silhouette extraction (silhouettes.hpp) and every object-based
// shadow method (shadow volumes, wedges, DCS) start from it [Forest 2008 §2.2.1].
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "penumbra/scene/mesh.hpp"

namespace penumbra {

enum class EdgeKind : uint8_t {
  manifold,      // exactly two faces, traversing the edge in opposite directions
  boundary,      // exactly one face: an open border
  non_manifold,  // three or more faces
  inconsistent,  // two faces traversing the edge the same way (orientation flips across it)
};

/// One adjacent face of an edge: sign = +1 if the face traverses the edge v0 → v1, −1 if v1 → v0.
struct EdgeFace {
  uint32_t face = 0;
  int32_t sign = 0;
};

/// An undirected edge between two welded vertices, v0 < v1 (indices into Mesh::positions of the
/// welded representatives). Its faces are edge_faces[face_begin, face_begin + face_count).
struct MeshEdge {
  uint32_t v0 = 0;
  uint32_t v1 = 0;
  uint32_t face_begin = 0;
  uint32_t face_count = 0;
  EdgeKind kind = EdgeKind::manifold;
};

inline constexpr uint32_t kNoFace = 0xffffffffu;

/// Full edge adjacency of one mesh.
///
/// Welding tolerance: zero. Two vertices are merged iff their coordinates are bit-identical floats
/// (−0 = +0), by weld_positions (weld.hpp), as analyze_topology (topology.hpp) does, so
/// `penumbra info` and the shadow methods agree. Why no distance tolerance: shadow-volume counting
/// is exact only if the extruded quads of two faces sharing an edge start from the very same two
/// points; moving vertices to close cracks would change the occluder the reference (Embree) sees. A
/// crack of any size stays a pair of boundary edges, which the signed-multiplicity rule
/// (silhouettes.hpp) handles correctly.
struct MeshEdges {
  /// For every vertex of the mesh, the index of the first vertex at the same position.
  std::vector<uint32_t> weld;
  /// Welded corners of every triangle (degenerate or out-of-range triangles: all kNoFace).
  std::vector<std::array<uint32_t, 3>> faces;
  /// The three edges of every face: face_edges[f][c] is the edge from corner c to corner c+1.
  std::vector<std::array<uint32_t, 3>> face_edges;
  std::vector<MeshEdge> edges;
  std::vector<EdgeFace> edge_faces;

  size_t manifold_edges = 0;
  size_t boundary_edges = 0;
  size_t non_manifold_edges = 0;
  size_t inconsistent_edges = 0;
  size_t skipped_faces = 0;  // degenerate after welding or with out-of-range indices

  bool face_valid(size_t f) const { return faces[f][0] != kNoFace; }
  /// True iff every edge is manifold (closed, consistently oriented 2-manifold) and there are
  /// faces.
  bool closed_manifold() const { return !edges.empty() && manifold_edges == edges.size(); }
};

MeshEdges build_mesh_edges(const Mesh& mesh);

}  // namespace penumbra
