#include "penumbra/scene/orientation.hpp"

#include <cmath>
#include <utility>
#include <vector>

#include "penumbra/scene/silhouettes.hpp"

namespace penumbra {

Mesh reorient(const Mesh& mesh, const MeshEdges& edges, Reorientation* report) {
  const size_t nf = edges.faces.size();
  // flip[f]: 0/1 relative to the component's seed face; component id per face.
  std::vector<int8_t> flip(nf, -1);
  std::vector<uint32_t> component(nf, 0), queue;
  std::vector<std::vector<uint32_t>> members;
  std::vector<uint8_t> orientable;
  for (size_t seed = 0; seed < nf; ++seed) {
    if (!edges.face_valid(seed) || flip[seed] >= 0) continue;
    const uint32_t id = static_cast<uint32_t>(members.size());
    members.emplace_back();
    orientable.push_back(1);
    flip[seed] = 0;
    queue.assign(1, static_cast<uint32_t>(seed));
    for (size_t head = 0; head < queue.size(); ++head) {
      const uint32_t f = queue[head];
      component[f] = id;
      members[id].push_back(f);
      for (int c = 0; c < 3; ++c) {
        const MeshEdge& e = edges.edges[edges.face_edges[f][c]];
        if (e.face_count != 2) continue;  // boundary or non-manifold: no constraint
        const EdgeFace& a = edges.edge_faces[e.face_begin];
        const EdgeFace& b = edges.edge_faces[e.face_begin + 1];
        const EdgeFace& self = a.face == f ? a : b;
        const EdgeFace& other = a.face == f ? b : a;
        if (other.face == f) continue;
        // Opposite traversal after flipping: sign_f·(−1)^flip_f = −sign_h·(−1)^flip_h.
        const int8_t want = static_cast<int8_t>(flip[f] ^ (self.sign == other.sign ? 1 : 0));
        if (flip[other.face] < 0) {
          flip[other.face] = want;
          queue.push_back(other.face);
        } else if (flip[other.face] != want) {
          orientable[id] = 0;
        }
      }
    }
  }
  Reorientation r;
  Mesh out = mesh;
  for (size_t id = 0; id < members.size(); ++id) {
    if (!orientable[id]) {
      ++r.non_orientable;
      continue;
    }
    size_t ones = 0;
    for (uint32_t f : members[id]) ones += flip[f] == 1;
    const int8_t reverse = ones * 2 > members[id].size() ? 0 : 1;  // flip the minority
    for (uint32_t f : members[id]) {
      if ((flip[f] ^ reverse) == 1) continue;
      std::swap(out.triangles[f].v[1], out.triangles[f].v[2]);
      ++r.flipped;
    }
  }
  // A flipped face keeps its vertex normals (shading is not ours to change): only the winding,
  // which the shadow methods read through face_side, is reversed.
  if (report) *report = r;
  return out;
}

HoleGeometry hole_geometry(const Mesh& mesh, const MeshEdges& edges) {
  HoleGeometry h;
  std::vector<SilhouetteEdge> boundary;
  for (size_t e = 0; e < edges.edges.size(); ++e) {
    const MeshEdge& edge = edges.edges[e];
    if (edge.kind != EdgeKind::boundary) continue;
    const int32_t sign = edges.edge_faces[edge.face_begin].sign;
    SilhouetteEdge s;
    s.edge = static_cast<uint32_t>(e);
    s.from = sign > 0 ? edge.v0 : edge.v1;
    s.to = sign > 0 ? edge.v1 : edge.v0;
    s.multiplicity = 1;
    boundary.push_back(s);
  }
  for (const std::vector<uint32_t>& loop : silhouette_loops(boundary)) {
    DVec3 area(0.0);
    for (uint32_t k : loop)
      area += 0.5 * glm::cross(DVec3(mesh.positions[boundary[k].from]),
                               DVec3(mesh.positions[boundary[k].to]));
    h.hole_area += glm::length(area);
    ++h.loops;
  }
  for (size_t f = 0; f < edges.faces.size(); ++f) {
    if (!edges.face_valid(f)) continue;
    const auto& w = edges.faces[f];
    const DVec3 p0(mesh.positions[w[0]]);
    h.surface_area += 0.5 * glm::length(glm::cross(DVec3(mesh.positions[w[1]]) - p0,
                                                   DVec3(mesh.positions[w[2]]) - p0));
  }
  return h;
}

}  // namespace penumbra

namespace penumbra {

double winding_number(const Mesh& mesh, const MeshEdges& edges, const DVec3& point) {
  double total = 0.0;
  for (size_t f = 0; f < edges.faces.size(); ++f) {
    if (!edges.face_valid(f)) continue;
    const auto& w = edges.faces[f];
    const DVec3 a = DVec3(mesh.positions[w[0]]) - point, b = DVec3(mesh.positions[w[1]]) - point,
                c = DVec3(mesh.positions[w[2]]) - point;
    const double la = glm::length(a), lb = glm::length(b), lc = glm::length(c);
    // Van Oosterom–Strackee: tan(Ω/2) = det(a, b, c) / (|a||b||c| + (a·b)|c| + (a·c)|b| +
    // (b·c)|a|).
    const double num = glm::dot(a, glm::cross(b, c));
    const double den =
        la * lb * lc + glm::dot(a, b) * lc + glm::dot(a, c) * lb + glm::dot(b, c) * la;
    total += 2.0 * std::atan2(num, den);
  }
  return total / (4.0 * 3.14159265358979323846);
}

bool point_on_surface(const Mesh& mesh, const MeshEdges& edges, const DVec3& point) {
  for (size_t f = 0; f < edges.faces.size(); ++f) {
    if (!edges.face_valid(f) || face_side(mesh, edges, f, point) != 0) continue;
    const auto& w = edges.faces[f];
    const DVec3 p0(mesh.positions[w[0]]), p1(mesh.positions[w[1]]), p2(mesh.positions[w[2]]);
    const DVec3 n = glm::cross(p1 - p0, p2 - p0);
    // Inside or on the border: the point is on the inner side of (or on) all three edges.
    const double s0 = glm::dot(glm::cross(p1 - p0, point - p0), n);
    const double s1 = glm::dot(glm::cross(p2 - p1, point - p1), n);
    const double s2 = glm::dot(glm::cross(p0 - p2, point - p2), n);
    if (s0 >= 0.0 && s1 >= 0.0 && s2 >= 0.0) return true;
  }
  return false;
}

}  // namespace penumbra
