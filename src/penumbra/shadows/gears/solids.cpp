#include "penumbra/shadows/gears/solids.hpp"

#include <tbb/parallel_sort.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cstring>
#include <numeric>

namespace penumbra::gears {

namespace {

uint32_t find_root(std::vector<uint32_t>& parent, uint32_t x) {
  while (parent[x] != x) x = parent[x] = parent[parent[x]];
  return x;
}

}  // namespace

Solids find_solids(const Scene& scene, const TriangleSoup& soup) {
  Solids out;
  const size_t n = soup.size();
  out.of_triangle.assign(n, kNoSolid);
  // Welded vertex ids: per mesh, its vertices sorted by position bits.
  std::vector<std::vector<uint32_t>> weld(scene.meshes.size());
  for (size_t m = 0; m < scene.meshes.size(); ++m) {
    const Mesh& mesh = scene.meshes[m];
    if (!mesh.casts_shadows || !scene.material_of(mesh).is_opaque()) continue;
    const size_t nv = mesh.positions.size();
    auto key = [&](uint32_t v) {
      std::array<uint32_t, 3> k;
      std::memcpy(k.data(), &mesh.positions[v], sizeof(k));
      return k;
    };
    std::vector<uint32_t> order(nv);
    std::iota(order.begin(), order.end(), 0u);
    tbb::parallel_sort(order.begin(), order.end(),
                       [&](uint32_t a, uint32_t b) { return key(a) < key(b); });
    weld[m].assign(nv, 0);
    for (size_t i = 0; i < nv; ++i)
      weld[m][order[i]] =
          i > 0 && key(order[i]) == key(order[i - 1]) ? weld[m][order[i - 1]] : order[i];
  }
  // Components: triangles joined by shared welded vertices (union-find over vertex ids, offset per
  // mesh), then the directed-edge balance of each.
  std::vector<uint32_t> vertex_base(scene.meshes.size() + 1, 0);
  for (size_t m = 0; m < scene.meshes.size(); ++m)
    vertex_base[m + 1] = vertex_base[m] + static_cast<uint32_t>(weld[m].size());
  std::vector<uint32_t> parent(vertex_base.back());
  std::iota(parent.begin(), parent.end(), 0u);
  auto vertex_id = [&](size_t t, int c) {
    const uint32_t m = soup.mesh[t];
    return vertex_base[m] + weld[m][scene.meshes[m].triangles[soup.prim[t]].v[c]];
  };
  for (size_t t = 0; t < n; ++t) {
    if (!soup.opaque[t] || weld[soup.mesh[t]].empty()) continue;
    const uint32_t a = find_root(parent, vertex_id(t, 0));
    for (int c = 1; c < 3; ++c) {
      const uint32_t b = find_root(parent, vertex_id(t, c));
      if (a != b) parent[b] = a;
    }
  }
  struct Edge {
    uint64_t key;  // (min id << 32) | max id
    int32_t sign;  // +1: traversed min → max
    uint32_t root;
  };
  std::vector<Edge> edges;
  edges.reserve(3 * n);
  std::vector<uint32_t> root_of(n, kNoSolid);
  for (size_t t = 0; t < n; ++t) {
    if (!soup.opaque[t] || weld[soup.mesh[t]].empty()) continue;
    root_of[t] = find_root(parent, vertex_id(t, 0));
    for (int c = 0; c < 3; ++c) {
      const uint64_t a = vertex_id(t, c), b = vertex_id(t, (c + 1) % 3);
      if (a == b) continue;
      edges.push_back({std::min(a, b) << 32 | std::max(a, b), a < b ? 1 : -1, root_of[t]});
    }
  }
  tbb::parallel_sort(edges.begin(), edges.end(),
                     [](const Edge& x, const Edge& y) { return x.key < y.key; });
  std::vector<uint8_t> open(parent.size(), 0);
  for (size_t i = 0; i < edges.size();) {
    size_t j = i;
    int sum = 0;
    for (; j < edges.size() && edges[j].key == edges[i].key; ++j) sum += edges[j].sign;
    if (sum != 0) open[edges[i].root] = 1;
    i = j;
  }
  // Closed components by size; each with its light-space box.
  std::vector<uint32_t> size(parent.size(), 0);
  std::vector<Vec3> lo(parent.size(), Vec3(kInfinity)), hi(parent.size(), Vec3(-kInfinity));
  for (size_t t = 0; t < n; ++t) {
    const uint32_t r = root_of[t];
    if (r == kNoSolid || open[r]) continue;
    ++size[r];
    for (int c = 0; c < 3; ++c) {
      const Vec3 q(soup.x[c][t], soup.y[c][t], soup.z[c][t]);
      lo[r] = glm::min(lo[r], q), hi[r] = glm::max(hi[r], q);
    }
  }
  std::vector<uint32_t> roots;
  for (uint32_t r = 0; r < parent.size(); ++r)
    if (size[r] > 0) {
      const Vec3 margin = 1e-4f * (hi[r] - lo[r]) +
                          1e-4f * glm::max(glm::abs(lo[r]), glm::abs(hi[r])) + Vec3(1e-6f);
      lo[r] -= margin, hi[r] += margin;
      if (lo[r].z > 0.0f || hi[r].z < 0.0f) roots.push_back(r);  // the light is outside
    }
  std::stable_sort(roots.begin(), roots.end(),
                   [&](uint32_t a, uint32_t b) { return size[a] > size[b]; });
  if (roots.size() > kMaxSolids) roots.resize(kMaxSolids);
  std::vector<uint32_t> solid_of_root(parent.size(), kNoSolid);
  for (uint32_t s = 0; s < roots.size(); ++s) {
    solid_of_root[roots[s]] = s;
    out.lo.push_back(lo[roots[s]]);
    out.hi.push_back(hi[roots[s]]);
  }
  for (size_t t = 0; t < n; ++t)
    if (root_of[t] != kNoSolid) out.of_triangle[t] = solid_of_root[root_of[t]];
  return out;
}

}  // namespace penumbra::gears
