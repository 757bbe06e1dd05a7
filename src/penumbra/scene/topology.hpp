// Edge topology of a triangle mesh: open boundaries, non-manifold edges, orientation consistency.
#pragma once

#include <cstddef>

#include "penumbra/scene/mesh.hpp"

namespace penumbra {

/// Edge statistics of a triangle mesh after welding vertices by position.
///
/// Welding is exact (weld_positions, weld.hpp): two vertices are the same point iff their
/// coordinates are bit-identical floats (after mapping -0.0 to +0.0); there is no distance
/// tolerance, so nearly coincident vertices (cracks of any size) count as distinct and their edges
/// as boundary edges. Triangles whose welded corners are not three distinct vertices (or that index
/// out of range) are ignored.
struct MeshTopology {
  size_t edges = 0;               // distinct undirected edges
  size_t boundary_edges = 0;      // edges with exactly one adjacent triangle (open surface)
  size_t non_manifold_edges = 0;  // edges with more than two adjacent triangles
  size_t inconsistent_edges = 0;  // two adjacent triangles traversing the edge the same way
  /// True iff the mesh has triangles and every edge has exactly two adjacent triangles that
  /// traverse it in opposite directions (a closed, consistently oriented 2-manifold).
  bool closed_manifold = false;
};

MeshTopology analyze_topology(const Mesh& mesh);

}  // namespace penumbra
