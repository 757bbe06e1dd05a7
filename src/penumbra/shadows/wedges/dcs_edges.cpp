#include "penumbra/shadows/wedges/dcs_edges.hpp"

#include "penumbra/scene/silhouettes.hpp"

namespace penumbra::dcs {

EdgeSet build_edges(const wedge_pass::CasterMeshes& casters,
                    const std::vector<uint16_t>& mesh_class, const Light& light,
                    SilhouetteMode mode) {
  EdgeSet set;
  const bool area = light.shape != LightShape::point;
  for (size_t m = 0; m < casters.meshes.size(); ++m) {
    const Mesh& mesh = *casters.meshes[m];
    const MeshEdges& me = casters.edges[m];
    const std::vector<int8_t> centre = face_sides(mesh, me, light.center);
    // Face planes in double, and whether each cuts (or touches) the light [Forest 2008 §4.1.4].
    std::vector<DVec3> normal(me.faces.size(), DVec3(0.0));
    std::vector<double> offset(me.faces.size(), 0.0);
    std::vector<uint8_t> straddles(me.faces.size(), 0);
    for (size_t f = 0; f < me.faces.size(); ++f) {
      if (!me.face_valid(f)) continue;
      const auto& w = me.faces[f];
      const DVec3 p0(mesh.positions[w[0]]), p1(mesh.positions[w[1]]), p2(mesh.positions[w[2]]);
      normal[f] = glm::cross(p1 - p0, p2 - p0);
      offset[f] = glm::dot(normal[f], p0);
      if (mode == SilhouetteMode::light && area) {
        double lo = 0.0, hi = 0.0;
        light_range(light, normal[f], offset[f], lo, hi);
        straddles[f] = lo <= 0.0 && hi >= 0.0;
      }
    }
    for (const MeshEdge& edge : me.edges) {
      int32_t mc = 0;
      bool cut = false;
      for (uint32_t k = 0; k < edge.face_count; ++k) {
        const penumbra::EdgeFace& ef = me.edge_faces[edge.face_begin + k];
        mc += centre[ef.face] * ef.sign;
        cut = cut || straddles[ef.face];
      }
      if (mc == 0 && !cut) continue;
      const bool flip = mc < 0;
      Edge e;
      e.from = DVec3(mesh.positions[flip ? edge.v1 : edge.v0]);
      e.to = DVec3(mesh.positions[flip ? edge.v0 : edge.v1]);
      e.centre_multiplicity = flip ? -mc : mc;
      e.layer_class = mesh_class[m];
      if (cut) {
        e.face_begin = static_cast<uint32_t>(set.faces.size());
        for (uint32_t k = 0; k < edge.face_count; ++k) {
          const penumbra::EdgeFace& ef = me.edge_faces[edge.face_begin + k];
          set.faces.push_back({normal[ef.face], offset[ef.face], flip ? -ef.sign : ef.sign});
        }
        e.face_count = edge.face_count;
        ++set.straddling;
      }
      set.edges.push_back(e);
    }
  }
  return set;
}

void BlockWeights::assign(const EdgeSet& set, const std::vector<uint32_t>& entries,
                          const std::vector<uint32_t>& edge_of_entry) {
  const size_t n = entries.size();
  for (int f = 0; f < 2; ++f) {
    nx[f].assign(n, 0.0), ny[f].assign(n, 0.0), nz[f].assign(n, 0.0);
    d[f].assign(n, 0.0), sign[f].assign(n, 0.0);
  }
  constant.assign(n, 0.0);
  general.assign(n, 0);
  m.resize(n);
  for (size_t j = 0; j < n; ++j) {
    const Edge& e = set.edges[edge_of_entry[entries[j]]];
    if (e.face_count == 0) {
      constant[j] = e.centre_multiplicity;
    } else if (e.face_count > 2) {
      general[j] = 1;
    } else {
      for (uint32_t f = 0; f < e.face_count; ++f) {
        const EdgeFace& face = set.faces[e.face_begin + f];
        nx[f][j] = face.n.x, ny[f][j] = face.n.y, nz[f][j] = face.n.z;
        d[f][j] = face.d;
        sign[f][j] = face.sign;
      }
    }
  }
}

void BlockWeights::evaluate(const EdgeSet& set, const std::vector<uint32_t>& entries,
                            const std::vector<uint32_t>& edge_of_entry, const DVec3& p) {
  const size_t n = entries.size();
  const double px = p.x, py = p.y, pz = p.z;
  // −Σ side · sign (multiplicity_for), branch-free over the entries.
  for (size_t j = 0; j < n; ++j) {
    double w = constant[j];
    for (int f = 0; f < 2; ++f) {
      const double s = nx[f][j] * px + ny[f][j] * py + nz[f][j] * pz - d[f][j];
      w -= ((s > 0.0) - (s < 0.0)) * sign[f][j];
    }
    m[j] = static_cast<int32_t>(w);
  }
  for (size_t j = 0; j < n; ++j)
    if (general[j]) m[j] = multiplicity_for(set, set.edges[edge_of_entry[entries[j]]], p);
}

}  // namespace penumbra::dcs
