// The constant of integration of depth complexity sampling: the number of caster triangles the
// segment from each receiver p to the light centre c crosses [Forest 2008 §4.1.1], from shadow
// volumes (wedges/shadow_volume.hpp), with half the work on closed meshes.
//
// For a closed, consistently oriented 2-manifold M (MeshEdges::closed_manifold, a topological
// fact, not a heuristic) with generalized winding number w_M, the crossings of p → c alternate:
// crossing a face toward its front side (c in front: a light-facing face) changes w_M by −1,
// toward its back side by +1, so with X the light-facing faces crossed and E the others,
// w_M(c) − w_M(p) = E − X and
//     D_M(p, c) = X + E = 2·X + w_M(c) − w_M(p).
// X is the shadow-volume count of M's light-facing faces alone (about half of them). w_M(c) is one
// solid-angle sum per mesh; w_M(p) = w_M(camera) for every visible point, since the segment from
// the camera to the shadow origin crosses no surface (the primary ray's nearest hit, offset toward
// the camera). Alpha-textured meshes are excluded (primary rays pass through their holes), as are
// open, non-manifold and inconsistently wound meshes: those are counted whole.
#pragma once

#include <vector>

#include "penumbra/core/image.hpp"
#include "penumbra/scene/edges.hpp"
#include "penumbra/shadows/method.hpp"
#include "penumbra/shadows/wedges/shadow_volume.hpp"

namespace penumbra::dcs {

/// D(p, centre) for every active pixel over `meshes` (edges[k] the adjacency of meshes[k]).
Image<int32_t> centre_counts(const ShadowContext& ctx, const std::vector<const Mesh*>& meshes,
                             const std::vector<const MeshEdges*>& edges, const Vec3& centre,
                             const ShadowVolumePixels& pixels);

}  // namespace penumbra::dcs
