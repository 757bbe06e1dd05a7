// The per-light setup of depth complexity sampling [Forest 2008 ch. 4], shared by the CPU `dcs`
// (wedges/dcs.hpp) and its Vulkan twin, so both integrate the same edges, wedges, bins and
// centre counts: the pixel setup, the caster meshes, the layer classes by transmittance
// (§4.3.3), the silhouette edges w.r.t. the light with their per-receiver weights (§4.1.4), the
// centre counts (§4.1.1), the wedges binned to screen tiles, and the S-triangles of the
// perforated casters (§5.2.2).
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "penumbra/core/image.hpp"
#include "penumbra/shadows/method.hpp"
#include "penumbra/shadows/wedges/dcs.hpp"
#include "penumbra/shadows/wedges/dcs_edges.hpp"
#include "penumbra/shadows/wedges/pass.hpp"
#include "penumbra/shadows/wedges/stsv.hpp"

namespace penumbra::dcs {

/// Casters with one transmittance: class 0 is opaque (and alpha-textured), the others semi-opaque.
struct LayerClass {
  double transmittance = 0.0;
  std::vector<const Mesh*> meshes;
  Image<int32_t> centre_counts;  // D(c) of this class per pixel (§4.1.1)
};

struct Frame {
  wedge_pass::PixelSetup setup;
  wedge_pass::CasterMeshes casters;  // owns what `classes` points to
  std::vector<LayerClass> classes;
  EdgeSet edges;
  /// Whether there are wedges at all (an area light, edges, active pixels); bw.group[k] is the
  /// edge of wedge k.
  bool area = false;
  wedge_pass::BinnedWedges bw;
  stsv::StsvSet stsv;
  size_t alpha_triangles = 0;  // alpha-textured triangles treated as opaque (alpha=opaque)
};

/// The setup stages in order, each timed into `out.times` ("setup", "silhouettes", "init",
/// "wedges"); `stsv_ms` gets the S-triangles' build time. `prepared`: the casters' adjacency from
/// the method's prepare() (wedge_pass::caster_meshes of a scene with these meshes), or null to
/// build it here.
Frame prepare_frame(const ShadowContext& ctx, const DcsOptions& options, Visibility& out,
                    double& stsv_ms, const wedge_pass::CasterMeshes* prepared = nullptr);

}  // namespace penumbra::dcs
