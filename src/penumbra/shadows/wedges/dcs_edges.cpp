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
    // Face planes in double, and whether each cuts (or touches) the light [Forest §4.1.4].
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

}  // namespace penumbra::dcs
