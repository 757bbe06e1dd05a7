#include "penumbra/scene/silhouettes.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>

namespace penumbra {

void light_range(const Light& light, const DVec3& n, double d, double& lo, double& hi) {
  const DVec3 c(light.center);
  const double at_c = glm::dot(n, c) - d;
  double half = 0.0;
  switch (light.shape) {
    case LightShape::point:
      break;
    case LightShape::rect:
      half = 0.5 * (std::abs(glm::dot(n, DVec3(light.edge_u))) +
                    std::abs(glm::dot(n, DVec3(light.edge_v))));
      break;
    case LightShape::disk: {
      const DVec3 nd = glm::normalize(DVec3(light.normal));
      half = light.radius * glm::length(n - glm::dot(n, nd) * nd);
      break;
    }
    case LightShape::sphere:
      half = light.radius * glm::length(n);
      break;
  }
  lo = at_c - half;
  hi = at_c + half;
}

int face_side(const Mesh& mesh, const MeshEdges& edges, size_t face, const DVec3& point) {
  if (!edges.face_valid(face)) return 0;
  const auto& w = edges.faces[face];
  const DVec3 p0(mesh.positions[w[0]]), p1(mesh.positions[w[1]]), p2(mesh.positions[w[2]]);
  const double s = glm::dot(glm::cross(p1 - p0, p2 - p0), point - p0);
  return (s > 0.0) - (s < 0.0);
}

std::vector<int8_t> face_sides(const Mesh& mesh, const MeshEdges& edges, const Vec3& point) {
  std::vector<int8_t> sides(edges.faces.size());
  const DVec3 p(point);
  for (size_t f = 0; f < sides.size(); ++f)
    sides[f] = static_cast<int8_t>(face_side(mesh, edges, f, p));
  return sides;
}

std::vector<SilhouetteEdge> silhouette_from_sides(const MeshEdges& edges,
                                                  const std::vector<int8_t>& sides) {
  std::vector<SilhouetteEdge> out;
  for (size_t e = 0; e < edges.edges.size(); ++e) {
    const MeshEdge& edge = edges.edges[e];
    int32_t m = 0;
    for (uint32_t k = 0; k < edge.face_count; ++k) {
      const EdgeFace& ef = edges.edge_faces[edge.face_begin + k];
      m += sides[ef.face] * ef.sign;
    }
    if (m == 0) continue;
    SilhouetteEdge s;
    s.edge = static_cast<uint32_t>(e);
    s.from = m > 0 ? edge.v0 : edge.v1;
    s.to = m > 0 ? edge.v1 : edge.v0;
    s.multiplicity = std::abs(m);
    out.push_back(s);
  }
  return out;
}

std::vector<SilhouetteEdge> point_silhouette(const Mesh& mesh, const MeshEdges& edges,
                                             const Vec3& point) {
  return silhouette_from_sides(edges, face_sides(mesh, edges, point));
}

std::vector<uint32_t> light_silhouette_edges(const Mesh& mesh, const MeshEdges& edges,
                                             const Light& light) {
  const std::vector<int8_t> centre_sides = face_sides(mesh, edges, light.center);
  std::vector<uint8_t> straddles(edges.faces.size(), 0);
  for (size_t f = 0; f < edges.faces.size(); ++f) {
    if (!edges.face_valid(f)) continue;
    const auto& w = edges.faces[f];
    const DVec3 p0(mesh.positions[w[0]]), p1(mesh.positions[w[1]]), p2(mesh.positions[w[2]]);
    const DVec3 n = glm::cross(p1 - p0, p2 - p0);
    double lo = 0.0, hi = 0.0;
    light_range(light, n, glm::dot(n, p0), lo, hi);
    straddles[f] = lo <= 0.0 && hi >= 0.0 && light.shape != LightShape::point;
  }
  std::vector<uint32_t> out;
  for (size_t e = 0; e < edges.edges.size(); ++e) {
    const MeshEdge& edge = edges.edges[e];
    int32_t m = 0;
    bool cut = false;
    for (uint32_t k = 0; k < edge.face_count; ++k) {
      const EdgeFace& ef = edges.edge_faces[edge.face_begin + k];
      m += centre_sides[ef.face] * ef.sign;
      cut = cut || straddles[ef.face];
    }
    if (m != 0 || cut) out.push_back(static_cast<uint32_t>(e));
  }
  return out;
}

std::vector<std::vector<uint32_t>> silhouette_loops(const std::vector<SilhouetteEdge>& silhouette) {
  int32_t g = 0;
  for (const SilhouetteEdge& s : silhouette) g = std::gcd(g, s.multiplicity);
  // Outgoing copies per vertex, sorted by (from, silhouette index) for determinism.
  std::vector<std::pair<uint32_t, uint32_t>> out_copies;  // (from vertex, silhouette index)
  for (uint32_t i = 0; i < silhouette.size(); ++i)
    for (int32_t c = 0; c < silhouette[i].multiplicity / std::max(g, 1); ++c)
      out_copies.push_back({silhouette[i].from, i});
  std::sort(out_copies.begin(), out_copies.end());
  std::vector<uint8_t> used(out_copies.size(), 0);
  // cursor[k]: first possibly unused copy of the vertex group containing position k.
  const auto first_of = [&](uint32_t v) {
    return static_cast<size_t>(
        std::lower_bound(out_copies.begin(), out_copies.end(), std::make_pair(v, 0u)) -
        out_copies.begin());
  };
  std::vector<std::vector<uint32_t>> loops;
  for (size_t start = 0; start < out_copies.size(); ++start) {
    if (used[start]) continue;
    std::vector<uint32_t> loop;
    size_t k = start;
    const uint32_t origin = out_copies[start].first;
    for (;;) {
      used[k] = 1;
      const uint32_t idx = out_copies[k].second;
      loop.push_back(idx);
      const uint32_t v = silhouette[idx].to;
      if (v == origin) break;
      size_t j = first_of(v);
      while (j < out_copies.size() && out_copies[j].first == v && used[j]) ++j;
      if (j >= out_copies.size() || out_copies[j].first != v)
        break;  // unbalanced input: open chain
      k = j;
    }
    loops.push_back(std::move(loop));
  }
  return loops;
}

}  // namespace penumbra
