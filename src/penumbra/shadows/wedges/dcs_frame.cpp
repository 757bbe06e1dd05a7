#include "penumbra/shadows/wedges/dcs_frame.hpp"

#include <algorithm>
#include <chrono>
#include <map>

#include "penumbra/core/stats.hpp"
#include "penumbra/shadows/wedges/dcs_init.hpp"
#include "penumbra/shadows/wedges/shadow_volume.hpp"

namespace penumbra::dcs {

Frame prepare_frame(const ShadowContext& ctx, const DcsOptions& options, Visibility& out,
                    double& stsv_ms, const wedge_pass::CasterMeshes* prepared) {
  using namespace wedge_pass;
  const Light& light = ctx.light;
  Frame fr;
  // Per-frame setup: pixel boxes and screen setup for the wedges, the shadow-volume pixel part,
  // the casters' adjacency; the layer classes by transmittance (§4.3.3).
  auto start = std::chrono::steady_clock::now();
  fr.setup = pixel_setup(ctx);
  fr.casters = prepared ? *prepared : caster_meshes(ctx.scene);
  CasterMeshes& casters = fr.casters;
  // Forest 2008 §5.3 Algorithm 12 lines 5–6: the perforated triangles leave the opaque machinery.
  stsv::Perforated perforated;
  if (options.alpha_stsv) perforated = stsv::take_perforated(ctx.scene, casters);
  std::vector<LayerClass>& classes = fr.classes;
  classes.resize(1);
  std::map<float, uint16_t> class_of_t;
  std::vector<uint16_t> mesh_class(casters.meshes.size(), 0);
  for (size_t m = 0; m < casters.meshes.size(); ++m) {
    const Material& mat = ctx.scene.material_of(*casters.meshes[m]);
    if (mat.transmittance > 0.0f) {
      auto [it, added] =
          class_of_t.emplace(mat.transmittance, static_cast<uint16_t>(classes.size()));
      if (added) classes.push_back({std::min(1.0, static_cast<double>(mat.transmittance)), {}, {}});
      mesh_class[m] = it->second;
    } else if (mat.alpha_texture >= 0 && !options.alpha_stsv) {
      fr.alpha_triangles += casters.meshes[m]->triangle_count();
    }
    classes[mesh_class[m]].meshes.push_back(casters.meshes[m]);
  }
  for (stsv::STriangle& t : perforated.triangles) {  // semi-opaque textured: their class [§5.5]
    if (t.transmittance <= 0.0f) continue;
    auto [it, added] = class_of_t.emplace(t.transmittance, static_cast<uint16_t>(classes.size()));
    if (added) classes.push_back({std::min(1.0, static_cast<double>(t.transmittance)), {}, {}});
    t.layer_class = it->second;
  }
  out.times.add("setup", elapsed_ms(start));

  start = std::chrono::steady_clock::now();
  fr.edges = build_edges(casters, mesh_class, light, options.silhouettes);
  out.times.add("silhouettes", elapsed_ms(start));

  // §4.1.1: the constant of integration, the shadow-volume count from the light centre.
  start = std::chrono::steady_clock::now();
  const Vec3 centre = hard_shadow_point(light);
  for (size_t j = 0; j < classes.size(); ++j) {
    std::vector<const MeshEdges*> class_edges;
    for (size_t m = 0; m < casters.meshes.size(); ++m)
      if (mesh_class[m] == j) class_edges.push_back(&casters.edges[m]);
    classes[j].centre_counts =
        centre_counts(ctx, classes[j].meshes, class_edges, centre, fr.setup.volume);
  }
  out.times.add("init", elapsed_ms(start));

  // Wedges of every edge and their tile bins (point light: none, the counts are the answer).
  start = std::chrono::steady_clock::now();
  fr.area = light.shape != LightShape::point && !fr.edges.edges.empty() && fr.setup.any_active;
  if (fr.area) {
    std::vector<WedgeEdge> wedge_edges(fr.edges.edges.size());
    for (size_t k = 0; k < fr.edges.edges.size(); ++k)
      wedge_edges[k] = {fr.edges.edges[k].from, fr.edges.edges[k].to, 1.0,
                        static_cast<uint32_t>(k)};
    fr.bw = build_and_bin(ctx, fr.setup, wedge_edges, wedge_light(light), options.construction);
  }
  out.times.add("wedges", elapsed_ms(start));

  // The S-triangles' volumes and their tile bins [Forest 2008 §5.1.2–5.1.3].
  start = std::chrono::steady_clock::now();
  fr.stsv = stsv::build_stsv(ctx, fr.setup, std::move(perforated));
  stsv_ms = elapsed_ms(start);
  return fr;
}

}  // namespace penumbra::dcs
