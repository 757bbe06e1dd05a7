// `shadow_volume`: exact hard shadows from one light point by shadow-volume counting, done per
// G-buffer pixel on the CPU ("deferred" shadow volumes) [Forest 2008 §2.2.1, §3.3.1, App. 3.A].
//
// Volume: the sum of every caster triangle's own shadow volume (its near cap, three side quads
// extruded to infinity, its far cap at infinity). Side quads of an edge shared by two triangles
// that face the light the same way cancel, so only silhouette quads remain, with the signed edge
// multiplicity of silhouettes.hpp (closed silhouettes m = 2, open boundaries m = 1, non-manifold
// edges whatever the sum gives). The per-pixel count is therefore
//     count(p) = number of caster triangles crossed by the segment p → light
// for ANY mesh (closed, open, non-manifold, inconsistently oriented): 0 = lit. This is what the
// soft methods (wedges, DCS) start from [Forest 2008 §4.1.1].
//
// Counting (z-fail, from infinity [Forest 2008 App. 3.A]): for each pixel's shadow origin p, the
// ray from p away from the camera crosses the volume boundary; each crossing adds +w where the face
// is back-facing from the camera (the ray leaves) and −w where it is front-facing (it enters). The
// faces are the near caps, silhouette quads and far caps; quads and far caps have vertices at
// infinity (homogeneous w = 0), so extrusion is exact. Nothing is needed at the camera, so a
// camera inside a shadow volume is correct by construction, and there is no near-plane problem.
//
// Robustness: each face is "rasterized" on the sphere of directions around the camera — pixel p
// is inside face F iff q = p − camera is inside the cone of F, tested with one plane through the
// camera per face edge. Every such plane is computed once per edge (a canonical function of its
// two vertex ids, in double) and used with opposite signs by the two faces sharing the edge, with
// a top-left tie rule for q exactly on it: adjacent faces never both count a pixel nor both miss
// it (watertight), whatever the thread count. The depth test "is the face behind p" is a plane
// test against the face's own plane (far caps are always behind). Each test uses the exact shadow
// origin p (not the pixel-centre ray), so the answer is the count at the very point raytrace
// shoots from. Pixels are enumerated per face over conservative screen spans (rasterizer clip +
// guard band + the largest offset between a shadow origin's projection and its pixel centre).
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "penumbra/raster/projection.hpp"
#include "penumbra/scene/edges.hpp"
#include "penumbra/shadows/method.hpp"

namespace penumbra {

struct ShadowVolumeStats {
  size_t caster_triangles = 0;
  size_t silhouette_edges = 0;  // edges with m ≠ 0 (each extrudes one quad of weight |m|)
  size_t faces = 0;             // near caps + far caps + silhouette quads
  size_t faces_on_screen = 0;   // of those, the ones reaching the screen and not seen edge-on
  uint64_t pixel_tests = 0;
  double edges_ms = 0.0, setup_ms = 0.0, count_ms = 0.0;
};

/// The hard-shadow light point of a light: its centre (for a sphere light the sphere's centre,
/// whereas LightFrame::center() moves toward each receiver).
inline Vec3 hard_shadow_point(const Light& light) {
  return light.center;
}

/// Per-pixel shadow-volume count for `light_point`: for every kActive pixel of `receivers`, the
/// number of caster triangles (meshes with casts_shadows; alpha and transmittance ignored) crossed
/// by the segment from gbuffer.shadow_origin(i) to light_point. Other pixels hold 0. `camera` must
/// be the one the G-buffer was rendered with.
Image<int32_t> shadow_volume_counts(const Scene& scene, const Camera& camera,
                                    const GBuffer& gbuffer, const Image<uint8_t>& receivers,
                                    const Vec3& light_point, ShadowVolumeStats* stats = nullptr);

/// The per-pixel part of the count (each shadow origin relative to the camera, the screen margin
/// and near plane they need), shared by any number of counts on one G-buffer — e.g. one per
/// caster group (wedges/pass.hpp).
struct ShadowVolumePixels {
  Projection proj;
  std::vector<DVec3> q;  // per pixel: shadow origin − camera (kActive pixels)
  double margin = 0.0, near = 0.0, guard = 1.0;
  bool any_active = false;
};
ShadowVolumePixels shadow_volume_pixels(const Camera& camera, const GBuffer& gbuffer,
                                        const Image<uint8_t>& receivers);
/// shadow_volume_counts with the per-pixel part already computed (for the same camera, G-buffer
/// and receivers).
Image<int32_t> shadow_volume_counts(const Scene& scene, const ShadowVolumePixels& pixels,
                                    const GBuffer& gbuffer, const Image<uint8_t>& receivers,
                                    const Vec3& light_point, ShadowVolumeStats* stats = nullptr);

/// One caster of an explicit count: a mesh (casting whatever its flag says), its prebuilt edges,
/// and optionally which of its faces take part (indexed like edges.faces; a face left out counts
/// as no face at all). What the wedge methods and `dcs` use to count caster groups and sub-meshes
/// without copying meshes or rebuilding their adjacency.
struct CountCaster {
  const Mesh* mesh = nullptr;
  const MeshEdges* edges = nullptr;
  const std::vector<uint8_t>* keep = nullptr;  // null: every face
};
Image<int32_t> shadow_volume_counts(std::span<const CountCaster> casters,
                                    const ShadowVolumePixels& pixels, const GBuffer& gbuffer,
                                    const Image<uint8_t>& receivers, const Vec3& light_point,
                                    ShadowVolumeStats* stats = nullptr);

/// The same for a shadow context, from hard_shadow_point(ctx.light).
Image<int32_t> shadow_volume_counts(const ShadowContext& ctx, ShadowVolumeStats* stats = nullptr);

}  // namespace penumbra
