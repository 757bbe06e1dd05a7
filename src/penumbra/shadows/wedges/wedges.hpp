// `wedges`: soft shadow volumes with penumbra wedges [Assarsson 2003 III §3, Assarsson 2003 IV
// §4–5; Forest 2008 §3.1, Algorithm 3, App. 3.B], on the CPU, per G-buffer pixel.
//
// Pass 1: the hard-shadow count from the light centre (wedges/shadow_volume.hpp). Pass 2: one wedge
// per silhouette edge from the light centre (wedges/geometry.hpp); for every pixel whose shadow
// origin lies inside it, the edge is projected onto the light and its signed coverage
// (wedges/coverage.hpp) is added (outer half: the edge occludes) or subtracted (inner half: the
// hard count over-estimates). Visible fraction V = 1 − clamp(count + Σ coverage, 0, 1).
//
// Layers. shadow_volume counts triangles crossed, so a closed mesh gives 2 per occluder and its
// silhouette edges have multiplicity 2; an open sheet gives 1. We count light-facing patches
// (open sheets, wedges/pass.hpp), so "1" means "one occluder covers the light" for every mesh —
// what the papers' stencil counts mean for closed meshes; a mesh with nothing facing the light
// centre is counted whole and divided by its layer count (2 for a closed 2-manifold, 1 otherwise).
//
// What it gets right and wrong (measured, docs/methods/wedges.md): exact for one planar convex
// occluder (Assarsson 2003 III §5.3: the silhouette seen from every light point is the one seen
// from the centre and nothing overlaps); elsewhere the single-silhouette approximation (the
// silhouette from the light centre stands for all light points) and the overlap error (coverages of
// different edges are summed, not unioned) remain, reduced by splitting the light (Assarsson 2003
// IV §5.2) and, for the overlap error between separate casters, by the overlap approximation
// (Assarsson 2003 IV §5.1, option `overlap`) or by penumbra-wedge blending (Forest 2008 §3.2,
// wedges/wedge_blend.hpp).
#pragma once

#include <cstdint>
#include <functional>
#include <memory>

#include "penumbra/shadows/method.hpp"
#include "penumbra/shadows/wedges/coverage.hpp"
#include "penumbra/shadows/wedges/geometry.hpp"
#include "penumbra/shadows/wedges/stsv.hpp"

namespace penumbra {

namespace wedge_pass {
struct BinnedWedges;
struct GroupCounts;
}  // namespace wedge_pass

struct WedgePass2Input;

struct WedgeOptions {
  /// The wedge construction [wedges/geometry.hpp]: Assarsson 2003 III §3.1 / IV §4.1 (moved
  /// vertex), or the tightest polyhedral hull of the edge's region.
  WedgeConstruction construction = WedgeConstruction::paper;
  int split =
      1;  // split a rectangular light into split × split sub-lights (Assarsson 2003 IV §5.2)
  /// Overlap approximation [Assarsson 2003 IV §5.1, eq. 1]: each group's coverage (hard count + its
  /// wedges, clamped) is computed apart and combined as max + ½ min. Groups are connected
  /// light-facing patches, each bounded by its silhouette loops (wedges/pass.hpp).
  bool overlap = false;
  /// Coverage of a clipped edge on a rectangular light: analytic sector minus triangle, or the 4D
  /// coverage texture of Assarsson 2003 III §3.3 (texture_n² × texture_n² entries, `lookup`
  /// filtering). Round lights always use the analytic formula.
  bool texture = false;
  int texture_n = 32;
  CoverageTexture::Lookup lookup = CoverageTexture::Lookup::bilinear;
  /// Perforated (alpha-textured) triangles through soft textured shadow volumes, their bitmask
  /// V_coef added to the wedges' [Forest 2008 §5.2.1, wedges/stsv_mask.hpp]; false: solid.
  bool alpha_stsv = true;
  /// The table, built by wedge_visibility when null (the method builds it once).
  std::shared_ptr<const CoverageTexture> table;
  /// Pass 2 done elsewhere (the Vulkan backend): per pixel of (sub-)light `light` the occluded
  /// fraction per channel (see WedgePass2Input). Null: the CPU's pass. The RGB coverage texture
  /// (a textured light with `texture`) stays on the CPU.
  std::function<Image<DVec3>(const ShadowContext& ctx, const Light& light,
                             const WedgePass2Input& input)>
      pass2;
};

/// What pass 2 done elsewhere receives: the binned wedges and, per pixel, the hard counts of the
/// caster groups (wedge_pass::for_each_group). Without the overlap approximation every wedge is in
/// group 0 (`grouped` false) and group 0's count is the layered hard count, so folding the groups
/// by max + ½ min gives the clamped sum; with it, the groups of `wedges` and their counts. The
/// result per active pixel: the folded occluded fraction per channel (equal channels for an
/// untextured light) — the CPU's `total`, or its clamped `sum`.
struct WedgePass2Input {
  const wedge_pass::BinnedWedges& wedges;
  const wedge_pass::GroupCounts& counts;
  bool grouped = false;
  const LightEmission* emission = nullptr;  // a textured rectangle's (sub-)light, else null
  /// The coverage texture in place of the analytic area (a rectangle with `texture`), else null.
  const CoverageTexture* table = nullptr;
  CoverageTexture::Lookup lookup = CoverageTexture::Lookup::bilinear;
};

struct WedgeStats {
  size_t silhouette_edges = 0;
  size_t wedges = 0;
  size_t sub_lights = 0;
  uint64_t pixel_tests = 0;     // (pixel, wedge) pairs tested against the wedge planes
  uint64_t pixels_inside = 0;   // of those, inside the wedge
  uint64_t pixels_covered = 0;  // of those, with a nonzero coverage (the edge cuts the light)
  /// Pass 2 ran on a device (WedgeOptions::pass2), which does not count its pixel tests: the
  /// three counters above are then left out of the report rather than reported as 0.
  bool pass2_on_device = false;
  uint64_t plane_fallbacks = 0;  // pixels in the light's plane: no coverage (hard count only)
  size_t wedge_fallbacks = 0;    // wedges missing a plane of their construction (looser)
  double silhouettes_ms = 0.0, pass1_ms = 0.0, wedges_ms = 0.0, pass2_ms = 0.0;
  stsv::Summary stsv;  // the S-triangles' pass (alpha=stsv)
};

/// Writes the stage times and counters both wedge methods report into `vis`; the second pass's
/// stage is named `pass2_stage`.
void report_wedge_stats(const WedgeStats& stats, const char* pass2_stage, Visibility& vis);

struct OptionSpec;
class MethodOptions;
/// The `construction` option both wedge methods declare (registry.hpp), and its value.
OptionSpec wedge_construction_option();
WedgeConstruction wedge_construction_of(const MethodOptions& options);

/// Visible fraction of ctx.light for every kActive pixel (others 1). For a textured rectangular
/// light also the per-channel visible fraction in `lit_rgb` (when given; left untouched for
/// other lights) and V = its Rec. 709 luminance ratio; with `split`, each sub-light carries its
/// own part of the texture and the sub-lights are weighted by their emitted power per channel.
/// `prepared`: the casters' adjacency from the method's prepare() (wedge_pass::caster_meshes of a
/// scene with ctx.scene's meshes); built here when null.
Image<float> wedge_visibility(const ShadowContext& ctx, const WedgeOptions& options,
                              WedgeStats* stats = nullptr, Image<Vec3>* lit_rgb = nullptr,
                              const wedge_pass::CasterMeshes* prepared = nullptr);

/// The `wedges` options of a method's option values, and the method for given options (the
/// registry's entry is make_wedges(wedge_options_of(o))).
WedgeOptions wedge_options_of(const MethodOptions& options);
std::unique_ptr<ShadowMethod> make_wedges(WedgeOptions options);

}  // namespace penumbra
