#include "penumbra/scene/topology.hpp"

#include <array>
#include <bit>
#include <cstdint>
#include <unordered_map>
#include <vector>

namespace penumbra {

namespace {

using PositionKey = std::array<uint32_t, 3>;

struct PositionKeyHash {
  size_t operator()(const PositionKey& k) const {
    uint64_t h = 0xcbf29ce484222325ull;
    for (uint32_t x : k) {
      h ^= x;
      h *= 0x100000001b3ull;
      h ^= h >> 29;
    }
    return static_cast<size_t>(h);
  }
};

uint32_t float_bits(float x) {
  return std::bit_cast<uint32_t>(x + 0.0f);  // + 0.0f maps -0.0 to +0.0
}

/// Adjacent-face count of one undirected edge (lo, hi), and how many faces traverse it lo → hi.
struct EdgeUse {
  uint32_t faces = 0;
  uint32_t forward = 0;
};

}  // namespace

MeshTopology analyze_topology(const Mesh& mesh) {
  // Weld: map every vertex index to the index of the first vertex at the same position.
  std::vector<uint32_t> weld(mesh.positions.size());
  {
    std::unordered_map<PositionKey, uint32_t, PositionKeyHash> first;
    first.reserve(mesh.positions.size());
    for (size_t i = 0; i < mesh.positions.size(); ++i) {
      const Vec3& p = mesh.positions[i];
      const PositionKey key{float_bits(p.x), float_bits(p.y), float_bits(p.z)};
      weld[i] = first.try_emplace(key, static_cast<uint32_t>(i)).first->second;
    }
  }

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
