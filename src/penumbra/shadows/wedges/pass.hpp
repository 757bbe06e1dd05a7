// The machinery shared by `wedges` (wedges/wedges.hpp) and `wedge_blend` (wedges/wedge_blend.hpp):
// light hull, per-frame pixel setup, caster groups and their silhouette edges, hard counts (pass
// 1), wedge construction and screen binning, and the per-pixel visit of the wedges of a pixel's
// tile (pass 2) [Assarsson 2003 III §3.1–3.2, Assarsson 2003 IV §4; Forest 2008 §3.1, Algorithm 3].
//
// Groups. Paper IV §5.1's overlap approximation and Forest 2008 §3.2's blending both need the hard
// count and the wedge coverage of each silhouette loop separately (Forest 2008 Algorithm 4 line 4:
// "render_silhouette_shadow_volumes(edges)"). A loop's hard count needs a surface it bounds, so
// we group by light-facing patch: the faces that face the light centre, connected across
// manifold edges whose two faces both do (for an open mesh, back-facing faces form patches too:
// a sheet blocks light from either side; a mesh with a few holes counts as closed,
// solid_for_wedges). Each patch is an open sheet whose boundary is made of
// silhouette loops from the light centre, so
//   - its hard count is the number of its faces the segment to the light centre crosses
//     (shadow_volume_counts of the patch alone, layers 1), and the patches' counts sum to the
//     mesh's layered count;
//   - its wedges are its boundary edges, i.e. every silhouette edge belongs to exactly one patch
//     (an open fold edge to two, with multiplicity 1 each: the same total).
// One patch per loop for a convex occluder (each sphere of `spheres`, the `quad`); a patch
// bounded by several loops (a ring's outer and inner loops, a face region with a back-facing
// hole) keeps them together because their hard counts cannot be separated; separate parts of one
// mesh that face the light (the bunny's ear and body) are separate groups, which is what lets
// blending correct their overlap. A mesh with no light-facing face (the centre inside a closed
// mesh) stays whole.
#pragma once

#include <algorithm>
#include <cstdint>
#include <functional>
#include <memory>
#include <vector>

#include "penumbra/core/parallel.hpp"
#include "penumbra/raster/projection.hpp"
#include "penumbra/render/receivers.hpp"
#include "penumbra/scene/edges.hpp"
#include "penumbra/shadows/exact/projection.hpp"
#include "penumbra/shadows/method.hpp"
#include "penumbra/shadows/wedges/coverage.hpp"
#include "penumbra/shadows/wedges/geometry.hpp"
#include "penumbra/shadows/wedges/screen.hpp"
#include "penumbra/shadows/wedges/shadow_volume.hpp"

namespace penumbra::wedge_pass {

inline constexpr int kTile = 16;  // pixels per tile side: wedges are binned to tiles

/// Points whose convex hull holds every emitting point of the light from any receiver (empty for
/// a point light).
std::vector<DVec3> light_hull_points(const Light& light);

/// The light as the wedge construction sees it (wedges/geometry.hpp): hull points, centre (the
/// hard-shadow point), bounding sphere of a disk or sphere, plane of a one-sided light.
WedgeLight wedge_light(const Light& light);

/// 2 for a closed, consistently oriented mesh (every segment crosses it an even number of times),
/// 1 otherwise.
inline int mesh_layers(const MeshEdges& e) {
  return e.closed_manifold() ? 2 : 1;
}

/// Whether the wedge methods treat a mesh as a closed solid: its light-facing faces alone stand
/// for it (make_casters). Decided from orientation and hole geometry (scene/orientation.hpp), on
/// the re-oriented mesh: a manifold, consistently oriented mesh whose holes (boundary loops, by
/// vector area) total at most kHoleAreaFraction of its surface area — a closed mesh, or a scanned
/// model with a few small holes (the dragon). Counting every face of such a mesh as an open sheet
/// would put two layers everywhere, with every silhouette edge's coverage counted twice (the
/// dragon's `wedges` error 0.120 instead of 0.058 at 512²); the price is that a light segment
/// passing through a hole and then through the far side is counted lit, which confines the error
/// to the hard shadows of the holes. An open bowl (hole ≈ half its area) or any curved sheet is
/// open whatever its tessellation: every face counts.
inline constexpr double kHoleAreaFraction = 0.01;
bool solid_for_wedges(const Mesh& mesh, const MeshEdges& e);

/// The emission texture of a textured light; a clear error naming `method` if the light names a
/// texture the scene does not have.
const Texture& emission_texture(const Scene& scene, const Light& light, const char* method);

/// V from per-channel occluded fractions (of each channel's emitted power `total`): the
/// per-channel visible fraction into `rgb`, and their Rec. 709 luminance ratio weighted by the
/// light's per-channel emission (light_weights.hpp) as the result.
float rgb_visibility(const DVec3& occluded, const DVec3& total, Vec3& rgb);

/// Per-pixel data shared by all wedges of a frame.
struct PixelSetup {
  WedgeScreenSetup screen;
  double margin = 0.0;  // max offset between a shadow origin's projection and its pixel centre
  bool any_active = false;
  /// Per kTile × kTile tile (row-major): the world-space box of its active shadow origins (empty:
  /// lo > hi). A wedge whose planes all miss a tile's box skips the tile — the CPU form of the
  /// GPU's hierarchical depth culling of wedge fragments [Assarsson 2003 IV §4.4].
  int tiles_x = 0, tiles_y = 0;
  std::vector<DVec3> tile_lo, tile_hi;
  /// The per-pixel part of the hard counts, shared by every (sub-)light and group.
  ShadowVolumePixels volume;
};
PixelSetup pixel_setup(const ShadowContext& ctx);

/// The caster groups: the light-facing patches of every caster mesh seen from `centre` (see the
/// header comment). Plain `wedges` sums their counts (layered_counts: one count over all of
/// them, which only visits the light-facing half of a closed mesh's triangles); the overlap
/// approximation and `wedge_blend` keep them apart (group_counts).
struct Casters {
  std::vector<std::unique_ptr<Mesh>> owned;             // patches
  std::vector<std::shared_ptr<const Mesh>> reoriented;  // keeps CasterMeshes::owned alive
  std::vector<const Mesh*> meshes;                      // one per group
  std::vector<MeshEdges> edges;
  std::vector<int> layers;
};
/// The caster meshes of a scene with their edge adjacency: built once per frame, shared by every
/// (sub-)light's make_casters. A mesh with inconsistently oriented faces is replaced by its
/// re-oriented copy (scene/orientation.hpp; the occluding triangles are the same), so one flipped
/// triangle does not turn a closed mesh into an open one with two layers everywhere; triangles
/// coincident with an earlier caster triangle (same three positions) are dropped, so coincident
/// geometry occludes once.
struct CasterMeshes {
  std::vector<const Mesh*> meshes;
  std::vector<MeshEdges> edges;
  std::vector<uint8_t> solid;                      // solid_for_wedges, per mesh
  std::vector<Bounds3> bounds;                     // per mesh
  std::vector<std::shared_ptr<const Mesh>> owned;  // the copies without duplicates, re-oriented
  size_t flipped_faces = 0, duplicate_faces = 0;
};
CasterMeshes caster_meshes(const Scene& scene);
Casters make_casters(const CasterMeshes& meshes, const Vec3& centre);
Casters make_casters(const Scene& scene, const Vec3& centre);

/// A silhouette edge from the light centre [Assarsson 2003 III §3.1]: weight = multiplicity /
/// layers.
struct WedgeEdge {
  DVec3 from{0.0}, to{0.0};
  double weight = 0.0;
  uint32_t group = 0;
};
/// In group order (so wedge indices, hence tile bins, are sorted by group).
std::vector<WedgeEdge> silhouette_edges(const Casters& casters, const Vec3& centre);

/// Pass 1 [Assarsson 2003 III §3.2, Forest 2008 Algorithm 3 line 1] over all groups: Σ count /
/// layers. `pixels`: the shared per-pixel setup (PixelSetup::volume), computed here when null.
Image<float> layered_counts(const ShadowContext& ctx, const Casters& casters, const Vec3& point,
                            const ShadowVolumePixels* pixels = nullptr);

/// The shadow-volume count of `casters` alone (every one casting, its prebuilt edges): triangles
/// crossed by the segment from each active pixel's shadow origin to `point`.
Image<int32_t> hard_counts(const ShadowContext& ctx, const std::vector<CountCaster>& casters,
                           const Vec3& point, const ShadowVolumePixels* pixels = nullptr);

/// Pass 1 per group: for every active pixel the nonzero (group, count / layers), sorted by group
/// (CSR: entries of pixel i are [begin[i], begin[i + 1])).
struct GroupCounts {
  std::vector<uint32_t> begin;
  std::vector<uint32_t> group;
  std::vector<float> value;
};
GroupCounts group_counts(const ShadowContext& ctx, const Casters& casters, const Vec3& point,
                         const ShadowVolumePixels* pixels = nullptr);

/// Bins convex screen hulls (wedges/screen.hpp) to the kTile × kTile tiles, widened by the
/// shadow-origin margin; may_hold(item, tile) then culls an item against the tile's world box
/// (PixelSetup::tile_lo/hi). Each bin is in item order. Shared by the wedges and the soft textured
/// shadow volumes (wedges/stsv.hpp).
std::vector<std::vector<uint32_t>> bin_hulls(
    const ShadowContext& ctx, const PixelSetup& setup, const std::vector<std::vector<DVec2>>& hulls,
    const std::function<bool(uint32_t item, size_t tile)>& may_hold);

/// The wedges of one (sub-)light and their 16×16 tile bins (each bin in wedge index order).
struct BinnedWedges {
  std::vector<Wedge> wedges;
  std::vector<uint32_t> group;  // per wedge
  int tiles_x = 0, tiles_y = 0;
  std::vector<std::vector<uint32_t>> bins;
  size_t degenerate = 0;  // wedges missing a plane of their construction (wedges/geometry.hpp)
};
/// Builds every edge's wedge with `construction` and bins its screen bound (wedges/screen.hpp,
/// generators: the wedge's top edge) to the tiles.
BinnedWedges build_and_bin(const ShadowContext& ctx, const PixelSetup& setup,
                           const std::vector<WedgeEdge>& edges, const WedgeLight& light,
                           WedgeConstruction construction);

/// Pass-2 counters.
struct PassCounters {
  uint64_t tests = 0, inside = 0, covered = 0, fallbacks = 0;
  PassCounters& operator+=(const PassCounters& o) {
    tests += o.tests;
    inside += o.inside;
    covered += o.covered;
    fallbacks += o.fallbacks;
    return *this;
  }
};

/// The light as seen from one pixel's point: projects and clips a wedge's edge, gives its
/// coverage [wedges/coverage.hpp; Assarsson 2003 IV §4.2].
class PixelLight {
 public:
  PixelLight(const Light& light, const LightFrame& fixed_frame, bool per_pixel_frame,
             const Vec3& origin);
  bool valid() const { return valid_; }
  bool round() const { return round_; }
  /// The projection from the point onto the light's uv (exact/projection.hpp).
  const LightProjection& projection() const { return lp_; }
  const DVec3& point() const { return p_; }
  /// The edge clipped to the light (uv), false if it misses it.
  bool clip(const Wedge& w, DVec2& a, DVec2& b) const;
  /// Sector minus triangle of a clipped uv segment (square or disk).
  double area(const DVec2& a, const DVec2& b) const {
    return round_ ? disk_sector_minus_triangle(a, b) : square_sector_minus_triangle(a, b);
  }
  /// The occluded fraction of the whole light the edge adds (outer half, > 0) or removes (inner
  /// half, < 0) for a uv area: τ orients light uv as seen from the point [wedges/wedges.cpp].
  double occlusion(const Wedge& w, double uv_area) const {
    return -tau_ * w.weight * uv_area * inv_area_;
  }
  /// +1 when light uv, seen from the point, turns the way the light's own uv does, −1 otherwise.
  double tau() const { return tau_; }

 private:
  bool valid_ = false, round_ = false;
  DVec3 p_{0.0};
  LightProjection lp_;
  double tau_ = 1.0, inv_area_ = 1.0;
};

/// Pass 2 driver: for every active pixel i (tile by tile, one tile row per task), calls
/// shade(i, light_or_null, bin, counters) and stores the float it returns in the result. The
/// PixelLight is null when the bin is empty or the point lies in the light's plane.
template <class Shade>
Image<float> run_pass2(const ShadowContext& ctx, const Light& light, const BinnedWedges& bw,
                       PassCounters& total, Shade&& shade) {
  const GBuffer& g = ctx.gbuffer;
  Image<float> vis(g.width, g.height, 1.0f);
  const bool per_pixel_frame = frame_depends_on_receiver(light);
  const LightFrame fixed_frame = light_frame(light, light.center);
  std::vector<PassCounters> rows(bw.tiles_y);
  parallel_rows(bw.tiles_y, [&](int ty) {
    PassCounters& c = rows[ty];
    for (int tx = 0; tx < bw.tiles_x; ++tx) {
      const std::vector<uint32_t>& bin = bw.bins[static_cast<size_t>(ty) * bw.tiles_x + tx];
      for (int y = ty * kTile; y < std::min(g.height, (ty + 1) * kTile); ++y) {
        for (int x = tx * kTile; x < std::min(g.width, (tx + 1) * kTile); ++x) {
          const size_t i = static_cast<size_t>(y) * g.width + x;
          if (ctx.receivers[i] != kActive) continue;
          if (bin.empty()) {
            vis[i] = shade(i, static_cast<const PixelLight*>(nullptr), bin, c);
            continue;
          }
          const PixelLight pl(light, fixed_frame, per_pixel_frame, g.shadow_origin(i));
          if (!pl.valid()) ++c.fallbacks;
          vis[i] = shade(i, pl.valid() ? &pl : nullptr, bin, c);
        }
      }
    }
  });
  for (const PassCounters& c : rows) total += c;
  return vis;
}

/// A wedge whose edge cuts the light as seen from a pixel's point: clipped uv segment and area.
struct CoveredEdge {
  uint32_t wedge = 0;
  DVec2 a{0.0}, b{0.0};
  double area = 0.0;
};

/// Visits the wedges of `bin` that hold the point and whose edge cuts the light (counting tests),
/// calling f(CoveredEdge) for each, in bin order.
template <class F>
void visit_covered(const PixelLight& pl, const BinnedWedges& bw, const std::vector<uint32_t>& bin,
                   size_t from, size_t to, PassCounters& c, F&& f) {
  for (size_t j = from; j < to; ++j) {
    const Wedge& w = bw.wedges[bin[j]];
    ++c.tests;
    if (!w.contains(pl.point())) continue;
    ++c.inside;
    CoveredEdge e;
    e.wedge = bin[j];
    if (!pl.clip(w, e.a, e.b)) continue;
    e.area = pl.area(e.a, e.b);
    if (e.area == 0.0) continue;
    ++c.covered;
    f(e);
  }
}

/// Per pixel, per group in group order (Assarsson 2003 IV §5.1, Forest 2008 Algorithm 4 lines 2–7):
/// calls f(group, hard count of the group, covered edges of the group) for every group with a
/// nonzero count at pixel i or a wedge in the bin. Count entries and bins are both sorted by group.
template <class F>
void for_each_group(const GroupCounts& gc, size_t i, const PixelLight* pl,
                    const std::vector<uint32_t>& bin, const BinnedWedges* bw, PassCounters& c,
                    F&& f) {
  thread_local std::vector<CoveredEdge> edges;
  uint32_t ci = gc.begin[i];
  const uint32_t ce = gc.begin[i + 1];
  size_t bi = 0;
  const size_t be = pl ? bin.size() : 0;
  while (ci < ce || bi < be) {
    uint32_t grp = ci < ce ? gc.group[ci] : UINT32_MAX;
    if (bi < be) grp = std::min(grp, bw->group[bin[bi]]);
    double count = 0.0;
    if (ci < ce && gc.group[ci] == grp) count = gc.value[ci++];
    size_t bj = bi;
    while (bj < be && bw->group[bin[bj]] == grp) ++bj;
    edges.clear();
    if (bj > bi)
      visit_covered(*pl, *bw, bin, bi, bj, c, [&](const CoveredEdge& e) { edges.push_back(e); });
    bi = bj;
    f(grp, count, static_cast<const std::vector<CoveredEdge>&>(edges));
  }
}

}  // namespace penumbra::wedge_pass
