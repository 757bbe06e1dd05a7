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

SolidComponents find_closed_components(const Scene& scene) {
  // The soup's numbering, from the scene alone: mesh and triangle of each, and whether it counts.
  std::vector<uint32_t> mesh_of, prim_of;
  std::vector<uint8_t> usable;
  std::vector<std::vector<uint32_t>> weld(scene.meshes.size());
  for (size_t m = 0; m < scene.meshes.size(); ++m) {
    const Mesh& mesh = scene.meshes[m];
    if (!mesh.casts_shadows) continue;
    const bool opaque = scene.material_of(mesh).is_opaque();
    // Welded vertex ids: per mesh, the first vertex at each position (scene/weld.hpp).
    if (opaque) weld[m] = weld_positions(mesh.positions);
    for (size_t t = 0; t < mesh.triangle_count(); ++t) {
      mesh_of.push_back(static_cast<uint32_t>(m));
      prim_of.push_back(static_cast<uint32_t>(t));
      usable.push_back(opaque && !weld[m].empty());
    }
  }
  const size_t n = mesh_of.size();
  // Components: triangles joined by shared welded vertices (union-find over vertex ids, offset per
  // mesh), then the directed-edge balance of each.
  std::vector<uint32_t> vertex_base(scene.meshes.size() + 1, 0);
  for (size_t m = 0; m < scene.meshes.size(); ++m)
    vertex_base[m + 1] = vertex_base[m] + static_cast<uint32_t>(weld[m].size());
  std::vector<uint32_t> parent(vertex_base.back());
  std::iota(parent.begin(), parent.end(), 0u);
  auto vertex_id = [&](size_t t, int c) {
    const uint32_t m = mesh_of[t];
    return vertex_base[m] + weld[m][scene.meshes[m].triangles[prim_of[t]].v[c]];
  };
  for (size_t t = 0; t < n; ++t) {
    if (!usable[t]) continue;
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
    if (!usable[t]) continue;
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
  // The closed components, numbered in the order of their roots.
  std::vector<uint32_t> triangles(nv, 0);
  for (size_t t = 0; t < n; ++t)
    if (root_of[t] != kNoSolid && !open[root_of[t]]) ++triangles[root_of[t]];
  SolidComponents out;
  std::vector<uint32_t> id_of_root(nv, kNoSolid);
  for (uint32_t r = 0; r < nv; ++r)
    if (triangles[r] > 0) {
      id_of_root[r] = static_cast<uint32_t>(out.size.size());
      out.size.push_back(triangles[r]);
    }
  out.of_triangle.assign(n, kNoSolid);
  for (size_t t = 0; t < n; ++t)
    if (root_of[t] != kNoSolid) out.of_triangle[t] = id_of_root[root_of[t]];
  return out;
}

Solids find_solids(const SolidComponents& components, const TriangleSoup& soup) {
  Solids out;
  const size_t n = soup.size();
  out.of_triangle.assign(n, kNoSolid);
  if (components.of_triangle.size() != n) return out;  // not this scene's: no solid
  // Each closed component's light-space box.
  const size_t count = components.size.size();
  std::vector<Vec3> lo(count, Vec3(kInfinity)), hi(count, Vec3(-kInfinity));
  for (size_t t = 0; t < n; ++t) {
    const uint32_t r = components.of_triangle[t];
    if (r == kNoSolid) continue;
    for (int c = 0; c < 3; ++c) {
      const Vec3 q(soup.x[c][t], soup.y[c][t], soup.z[c][t]);
      lo[r] = glm::min(lo[r], q), hi[r] = glm::max(hi[r], q);
    }
  }
  std::vector<uint32_t> roots;
  for (uint32_t r = 0; r < count; ++r) {
    const Vec3 margin =
        1e-4f * (hi[r] - lo[r]) + 1e-4f * glm::max(glm::abs(lo[r]), glm::abs(hi[r])) + Vec3(1e-6f);
    lo[r] -= margin, hi[r] += margin;
    if (lo[r].z > 0.0f || hi[r].z < 0.0f) roots.push_back(r);  // the light is outside
  }
  std::stable_sort(roots.begin(), roots.end(),
                   [&](uint32_t a, uint32_t b) { return components.size[a] > components.size[b]; });
  if (roots.size() > kMaxSolids) roots.resize(kMaxSolids);
  std::vector<uint32_t> solid_of(count, kNoSolid);
  for (uint32_t s = 0; s < roots.size(); ++s) {
    solid_of[roots[s]] = s;
    out.lo.push_back(lo[roots[s]]);
    out.hi.push_back(hi[roots[s]]);
  }
  for (size_t t = 0; t < n; ++t)
    if (components.of_triangle[t] != kNoSolid)
      out.of_triangle[t] = solid_of[components.of_triangle[t]];
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

Solids find_solids(const Scene& scene, const TriangleSoup& soup) {
  return find_solids(find_closed_components(scene), soup);
}

}  // namespace penumbra::gears
