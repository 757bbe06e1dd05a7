// Soft textured shadow volumes (STSV) [Forest 2008 ch. 5]: the shadows of perforated triangles
// (S-triangles: triangles of a material with an alpha texture), per light sample, for `dcs`,
// `wedges` and `wedge_blend`.
//
// What goes where (docs/methods/stsv.md):
//   - this file: which triangles are S-triangles, their volumes (§5.1.2, §5.5) and the point test
//     (§5.1.3), binned to the screen tiles of the wedges (wedges/pass.hpp, wedges/screen.hpp);
//   - wedges/stsv_lookup.hpp: per (pixel, S-triangle) the transform of eqs. 5.7–5.9 and per
//     light sample the barycentrics, uv (eq. 5.10) and alpha lookup;
//   - wedges/stsv_mask.hpp: the per-sample bitmask combined with the wedges' V_coef (§5.2.1);
//   - wedges/dcs.cpp: the covered opaque texels added to the depth complexity counters (§5.2.2).
//
// Classification. A triangle whose alpha texture is opaque over the whole uv box it covers is no
// S-triangle: it stays with the opaque meshes (the result is then bit for bit the opaque path's);
// one whose box holds only holes casts nothing and is dropped; every other one is an S-triangle.
// The nearest-texel rule is the one of `exact`, `raytrace` and `gears` (Texture::texel_index,
// alpha < kAlphaCutoff is a hole).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "penumbra/core/math.hpp"
#include "penumbra/scene/scene.hpp"
#include "penumbra/shadows/method.hpp"
#include "penumbra/shadows/wedges/geometry.hpp"
#include "penumbra/shadows/wedges/pass.hpp"

namespace penumbra {
struct OptionSpec;
class MethodOptions;
}  // namespace penumbra

namespace penumbra::stsv {

/// `<method>.alpha`: stsv (perforated triangles through their textured shadow volumes) or opaque
/// (every alpha-textured triangle a solid occluder, as before ch. 5).
OptionSpec alpha_option();
bool uses_stsv(const MethodOptions& options);

/// One S-triangle [Forest 2008 §5.1.1].
struct STriangle {
  DVec3 v0{0.0}, e1{0.0}, e2{0.0};  // world vertices v0, v0 + e1, v0 + e2
  /// M' of eq. 5.8: world offsets to coordinates in the basis (e1, e2, n), n = e1 × e2.
  glm::dmat3 to_triangle{1.0};
  const Mesh* mesh = nullptr;
  uint32_t prim = 0;
  Vec2 uv[3] = {};  // its vertices' uvs (0 without uvs: Mesh::uv_at)
  const Texture* alpha = nullptr;
  float transmittance = 0.0f;  // of an opaque texel (0: opaque; Forest 2008 §4.3.3)
  uint16_t layer_class = 0;    // dcs: the counters its opaque texels increment
};

/// Per side of the triangle's plane that the light reaches, a closed convex volume holding every
/// point that side of the light can be blocked from by the triangle (Wedge's plane set: inside iff
/// every plane holds the point). Two sides when the light crosses the plane [§5.5].
struct Volume {
  Wedge sides[2];
  int side_count = 0;
  bool contains(const DVec3& p) const {
    for (int k = 0; k < side_count; ++k)
      if (sides[k].contains(p)) return true;
    return false;
  }
  bool may_hold_box(const DVec3& lo, const DVec3& hi) const {
    for (int k = 0; k < side_count; ++k)
      if (sides[k].may_hold_box(lo, hi)) return true;
    return false;
  }
};

/// The volume of triangle v[0..2] [§5.1.2]: on the side of the light centre (the whole light on
/// one side of the plane, the paper's case) the front cap t' — the vertices moved toward the
/// centre to the distance of the closest one — and the outer planes of t''s edges, each the plane
/// through the edge that leaves the whole light outside (the outer quad of its penumbra wedge);
/// the back cap is at infinity. When the light crosses the plane, one volume per side from the
/// triangle itself and the part of the light on that side [§5.5]. A plane that cannot leave the
/// whole (part of the) light outside is left out, so the volume always holds the shadow region.
/// `light_points`: points whose convex hull holds the light (a point light: its position).
Volume build_volume(const DVec3 v[3], const std::vector<DVec3>& light_points, const DVec3& centre,
                    double scale);

/// How the triangles of a caster mesh with an alpha texture split (see the header comment).
enum class Footprint : uint8_t { opaque, holes, perforated };
Footprint classify(const Texture& alpha, const Vec2 uv[3]);

/// The S-triangles taken out of a frame's casters.
struct Perforated {
  std::vector<STriangle> triangles;
  size_t opaque_kept = 0;    // alpha-textured triangles opaque over their footprint
  size_t holes_dropped = 0;  // alpha-textured triangles over holes only
};
/// Splits the casters with an alpha texture: a mesh opaque over every triangle's footprint stays
/// as it is; otherwise its S-triangles are taken out, its opaque triangles stay as a new caster
/// mesh (kept alive by casters.owned) and its triangles over holes only are dropped.
Perforated take_perforated(const Scene& scene, wedge_pass::CasterMeshes& casters);

/// The S-triangles of a frame with their volumes and tile bins (wedges/pass.hpp kTile tiles).
struct StsvSet {
  std::vector<STriangle> triangles;
  std::vector<Volume> volumes;
  std::vector<std::vector<uint32_t>> bins;  // per tile, triangle indices in order
  int tiles_x = 0;
  size_t two_sided = 0;  // volumes with a side for each side of the light [§5.5]
  size_t opaque_kept = 0, holes_dropped = 0;
  bool empty() const { return triangles.empty(); }
  const std::vector<uint32_t>& bin_of_tile(int tx, int ty) const {
    return bins[static_cast<size_t>(ty) * tiles_x + tx];
  }
};
/// Builds the volumes of `perforated` for ctx.light and bins them (empty set for no S-triangle).
StsvSet build_stsv(const ShadowContext& ctx, const wedge_pass::PixelSetup& setup,
                   Perforated perforated);

/// Counters of the STSV pass.
struct StsvStats {
  uint64_t volume_tests = 0;  // (pixel, S-triangle) pairs of the pixel's tile bin
  uint64_t pairs = 0;         // of those, inside the volume with a projection meeting the light
  uint64_t lookups = 0;       // (pixel, S-triangle, sample) alpha lookups (sample on the triangle)
  uint64_t blocked = 0;       // of those, opaque texels
  StsvStats& operator+=(const StsvStats& o) {
    volume_tests += o.volume_tests;
    pairs += o.pairs;
    lookups += o.lookups;
    blocked += o.blocked;
    return *this;
  }
};
/// What a method reports of its STSV pass.
struct Summary {
  bool ran = false;  // alpha=stsv
  size_t triangles = 0, two_sided = 0, opaque_kept = 0, holes_dropped = 0, bin_entries = 0;
  StsvStats stats;
  double ms = 0.0;  // the volumes, bins and (wedge methods) per-sample pass
};
Summary summarize(const StsvSet& set, const StsvStats& stats, double ms);
/// Writes the counters (prefix `stsv_`) and the stage time `stsv` when the summary ran.
void report(const Summary& summary, Visibility& out);

}  // namespace penumbra::stsv
