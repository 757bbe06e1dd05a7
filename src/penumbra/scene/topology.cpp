#include "penumbra/scene/topology.hpp"

#include <cstdint>
#include <unordered_map>
#include <vector>

#include "penumbra/scene/weld.hpp"

namespace penumbra {

namespace {

/// Adjacent-face count of one undirected edge (lo, hi), and how many faces traverse it lo → hi.
struct EdgeUse {
  uint32_t faces = 0;
  uint32_t forward = 0;
};

}  // namespace

MeshTopology analyze_topology(const Mesh& mesh) {
  const std::vector<uint32_t> weld = weld_positions(mesh.positions);

  std::unordered_map<uint64_t, EdgeUse> edges;
  edges.reserve(mesh.triangles.size() * 2);
  size_t used_triangles = 0;
  for (const Triangle& t : mesh.triangles) {
    uint32_t w[3];
    bool valid = true;
    for (int c = 0; c < 3; ++c) {
      if (t.v[c] >= weld.size()) {
        valid = false;
        break;
      }
      w[c] = weld[t.v[c]];
    }
    if (!valid || w[0] == w[1] || w[1] == w[2] || w[0] == w[2]) continue;
    ++used_triangles;
    for (int c = 0; c < 3; ++c) {
      const uint32_t a = w[c], b = w[(c + 1) % 3];
      const uint32_t lo = a < b ? a : b, hi = a < b ? b : a;
      EdgeUse& use = edges[(static_cast<uint64_t>(lo) << 32) | hi];
      ++use.faces;
      if (a == lo) ++use.forward;
    }
  }

  MeshTopology topo;
  topo.edges = edges.size();
  for (const auto& [key, use] : edges) {
    if (use.faces == 1) {
      ++topo.boundary_edges;
    } else if (use.faces > 2) {
      ++topo.non_manifold_edges;
    } else if (use.forward != 1) {
      ++topo.inconsistent_edges;
    }
  }
  topo.closed_manifold = used_triangles > 0 && topo.boundary_edges == 0 &&
                         topo.non_manifold_edges == 0 && topo.inconsistent_edges == 0;
  return topo;
}

}  // namespace penumbra
