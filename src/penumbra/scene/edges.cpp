#include "penumbra/scene/edges.hpp"

#include <algorithm>
#include <array>

#include "penumbra/scene/weld.hpp"

namespace penumbra {

namespace {

/// One face's use of one edge, before grouping.
struct HalfEdge {
  uint32_t lo, hi, face;
  int32_t sign;
  uint32_t corner;
};

}  // namespace

MeshEdges build_mesh_edges(const Mesh& mesh) {
  MeshEdges out;
  const size_t nv = mesh.positions.size();
  out.weld = weld_positions(mesh.positions);

  const size_t nf = mesh.triangles.size();
  out.faces.assign(nf, {kNoFace, kNoFace, kNoFace});
  out.face_edges.assign(nf, {kNoFace, kNoFace, kNoFace});
  std::vector<HalfEdge> half;
  half.reserve(nf * 3);
  for (size_t f = 0; f < nf; ++f) {
    const Triangle& t = mesh.triangles[f];
    if (t.v[0] >= nv || t.v[1] >= nv || t.v[2] >= nv) {
      ++out.skipped_faces;
      continue;
    }
    const std::array<uint32_t, 3> w{out.weld[t.v[0]], out.weld[t.v[1]], out.weld[t.v[2]]};
    if (w[0] == w[1] || w[1] == w[2] || w[0] == w[2]) {
      ++out.skipped_faces;
      continue;
    }
    out.faces[f] = w;
    for (uint32_t c = 0; c < 3; ++c) {
      const uint32_t a = w[c], b = w[(c + 1) % 3];
      half.push_back({std::min(a, b), std::max(a, b), static_cast<uint32_t>(f), a < b ? 1 : -1, c});
    }
  }
  // Sort on one 64-bit edge key; the stable sort keeps faces in index order within an edge.
  std::stable_sort(half.begin(), half.end(), [](const HalfEdge& x, const HalfEdge& y) {
    return ((static_cast<uint64_t>(x.lo) << 32) | x.hi) <
           ((static_cast<uint64_t>(y.lo) << 32) | y.hi);
  });

  out.edge_faces.reserve(half.size());
  for (size_t k = 0; k < half.size();) {
    size_t e = k + 1;
    while (e < half.size() && half[e].lo == half[k].lo && half[e].hi == half[k].hi) ++e;
    MeshEdge edge;
    edge.v0 = half[k].lo;
    edge.v1 = half[k].hi;
    edge.face_begin = static_cast<uint32_t>(out.edge_faces.size());
    edge.face_count = static_cast<uint32_t>(e - k);
    const uint32_t id = static_cast<uint32_t>(out.edges.size());
    int32_t forward = 0;
    for (size_t j = k; j < e; ++j) {
      out.edge_faces.push_back({half[j].face, half[j].sign});
      out.face_edges[half[j].face][half[j].corner] = id;
      forward += half[j].sign > 0;
    }
    if (edge.face_count == 1) {
      edge.kind = EdgeKind::boundary;
      ++out.boundary_edges;
    } else if (edge.face_count > 2) {
      edge.kind = EdgeKind::non_manifold;
      ++out.non_manifold_edges;
    } else if (forward != 1) {
      edge.kind = EdgeKind::inconsistent;
      ++out.inconsistent_edges;
    } else {
      edge.kind = EdgeKind::manifold;
      ++out.manifold_edges;
    }
    out.edges.push_back(edge);
    k = e;
  }
  return out;
}

}  // namespace penumbra
