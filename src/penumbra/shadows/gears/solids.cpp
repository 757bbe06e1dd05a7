#include "penumbra/shadows/gears/solids.hpp"

#include <algorithm>
#include <array>
#include <numeric>

#include "penumbra/core/parallel.hpp"
#include "penumbra/scene/weld.hpp"

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
  // Welded vertex ids: per mesh, the first vertex at each position (scene/weld.hpp).
  // build_mesh_edges is not used: its edge sort takes longer than this whole function on 50–90 k
  // triangles, and it runs per light and frame.
  std::vector<std::vector<uint32_t>> weld(scene.meshes.size());
  for (size_t m = 0; m < scene.meshes.size(); ++m) {
    const Mesh& mesh = scene.meshes[m];
    if (!mesh.casts_shadows || !scene.material_of(mesh).is_opaque()) continue;
    weld[m] = weld_positions(mesh.positions);
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
  // Welded ids of every usable triangle's corners, its component.
  std::vector<uint32_t> root_of(n, kNoSolid);
  std::vector<std::array<uint32_t, 3>> ids(n);
  for (size_t t = 0; t < n; ++t) {
    if (!soup.opaque[t] || weld[soup.mesh[t]].empty()) continue;
    ids[t] = {vertex_id(t, 0), vertex_id(t, 1), vertex_id(t, 2)};
    root_of[t] = find_root(parent, ids[t][0]);
  }
  // Each vertex's directed edges out and in (CSR): the component is closed iff at every vertex
  // the two neighbour lists are equal as multisets (each a→b matched by as many b→a).
  const size_t nv = parent.size();
  std::vector<uint32_t> out_start(nv + 1, 0), in_start(nv + 1, 0);
  auto for_each_edge = [&](auto&& f) {
    for (size_t t = 0; t < n; ++t)
      if (root_of[t] != kNoSolid)
        for (int c = 0; c < 3; ++c)
          if (ids[t][c] != ids[t][(c + 1) % 3]) f(ids[t][c], ids[t][(c + 1) % 3]);
  };
  for_each_edge([&](uint32_t a, uint32_t b) { ++out_start[a + 1], ++in_start[b + 1]; });
  for (size_t v = 0; v < nv; ++v) out_start[v + 1] += out_start[v], in_start[v + 1] += in_start[v];
  std::vector<uint32_t> out_nbr(out_start[nv]), in_nbr(in_start[nv]);
  {
    std::vector<uint32_t> out_at(out_start.begin(), out_start.end() - 1);
    std::vector<uint32_t> in_at(in_start.begin(), in_start.end() - 1);
    for_each_edge(
        [&](uint32_t a, uint32_t b) { out_nbr[out_at[a]++] = b, in_nbr[in_at[b]++] = a; });
  }
  std::vector<uint8_t> unbalanced(nv, 0);
  parallel_chunks(nv, 4096, [&](size_t b, size_t e) {
    for (size_t v = b; v < e; ++v) {
      uint32_t* o0 = out_nbr.data() + out_start[v];
      uint32_t* o1 = out_nbr.data() + out_start[v + 1];
      uint32_t* i0 = in_nbr.data() + in_start[v];
      uint32_t* i1 = in_nbr.data() + in_start[v + 1];
      if (o1 - o0 != i1 - i0) {
        unbalanced[v] = 1;
        continue;
      }
      std::sort(o0, o1), std::sort(i0, i1);
      unbalanced[v] = !std::equal(o0, o1, i0);
    }
  });
  std::vector<uint8_t> open(nv, 0);
  for (uint32_t v = 0; v < nv; ++v)
    if (unbalanced[v]) open[find_root(parent, v)] = 1;
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
  // Depth maps: each face's xy box (widened past the cell rounding) over the cells it meets.
  constexpr int N = Solids::kMapSize;
  out.deepest.assign(roots.size() * N * N, -kInfinity);
  for (size_t t = 0; t < n; ++t) {
    const uint32_t s = out.of_triangle[t];
    if (s == kNoSolid) continue;
    Vec3 tlo(kInfinity), thi(-kInfinity);
    for (int c = 0; c < 3; ++c) {
      const Vec3 q(soup.x[c][t], soup.y[c][t], soup.z[c][t]);
      tlo = glm::min(tlo, q), thi = glm::max(thi, q);
    }
    const Vec3 slack = 1e-4f * (out.hi[s] - out.lo[s]);
    const int c0 = out.cell(s, tlo - slack), c1 = out.cell(s, thi + slack);
    const float z = thi.z + slack.z + 1e-4f * std::abs(thi.z);
    float* map = out.deepest.data() + static_cast<size_t>(s) * N * N;
    for (int j = c0 / N; j <= c1 / N; ++j)
      for (int i = c0 % N; i <= c1 % N; ++i) map[j * N + i] = std::max(map[j * N + i], z);
  }
  return out;
}

}  // namespace penumbra::gears
