// `wedge_blend`: penumbra-wedge blending [Forest 2008, Forest 2008 §3.2 (Algorithms 4–6, eq. 3.1)
// and its implementation §3.3.3–3.3.4], on the CPU, per G-buffer pixel, on top of the `wedges`
// machinery (wedges/pass.hpp: same wedges, hard counts, coverage and screen binning).
//
// Per caster group (a light-facing patch bounded by its silhouette loops, wedges/pass.hpp)
// an SV-buffer is built [§3.2.1, Algorithm 5]: the light, seen from the pixel, is cut at its
// centre into four parts of equal area (§3.2.1: "split the light source by its center, in four
// parts"); per part it holds
//   - occ: the occluded fraction of the part — the group's hard count from the light centre plus
//     the signed coverage of each of its wedges' edges clipped to the part (exact per part, since
//     the part is a cone from the centre: Σ parts = the `wedges` coverage);
//   - brect: the bounding rectangle of the occluded region of the part;
//   - the maxima in X and Y of the occluding (outer) edges [§3.3.3].
// Outer wedges are processed before inner ones [§3.3.3]: the hard count and the outer edges'
// regions give an upper bounding rectangle; the inner edges then shrink it, but never below the
// outer-edge maxima. The SV-buffer is then blended into the V-buffer [§3.2.2, Algorithm 6]:
// occ_v ← occ_s + occ_v − ε where ε = (A_v/B_v)(A_s/B_s)·β is the effective overlapped area
// heuristic (eq. 3.1; A occluded areas, B rectangle areas, β the area of the rectangles'
// intersection), and brect_v ← brect_s ∪ brect_v. V = 1 − mean over the parts of occ_v.
//
// For a single group (one planar convex occluder) the SV-buffer is the exact per-part occlusion,
// so `wedge_blend` equals `wedges` there (tested).
#pragma once

#include <array>
#include <functional>
#include <memory>

#include "penumbra/shadows/method.hpp"
#include "penumbra/shadows/registry.hpp"
#include "penumbra/shadows/wedges/pass.hpp"
#include "penumbra/shadows/wedges/wedges.hpp"

namespace penumbra {

struct WedgeBlendStats {
  WedgeStats wedges;      // silhouettes, wedges, pixel tests, stage times (blend in pass2)
  size_t groups = 0;      // SV-buffers (caster groups)
  uint64_t blends = 0;    // (pixel, part) blends of a nonzero SV part into a nonzero V part
  uint64_t overlaps = 0;  // of those, with intersecting rectangles (eq. 3.1 applied)
};

/// What the per-pixel blend done elsewhere receives: the binned wedges, the groups' hard counts,
/// a textured rectangle's emission (null otherwise) and the light's share in each of the four
/// parts (per channel: emitted power; ¼ for an untextured light).
struct WedgeBlendPass2Input {
  const wedge_pass::BinnedWedges& wedges;
  const wedge_pass::GroupCounts& counts;
  const LightEmission* emission = nullptr;
  std::array<DVec3, 4> parts{};
};

/// The per-pixel blend (Algorithms 4 lines 2–7, 5, 6) done elsewhere (the Vulkan backend): per
/// active pixel the occluded fraction per channel, Σ part share × V-buffer part, as the CPU pass
/// computes it (equal channels for an untextured light). Null: the CPU's pass.
using WedgeBlendPass2 =
    std::function<Image<DVec3>(const ShadowContext& ctx, const WedgeBlendPass2Input& input)>;

/// Visible fraction of ctx.light for every kActive pixel (others 1). For a textured rectangular
/// light also the per-channel visible fraction in `lit_rgb` (when given; left untouched for other
/// lights) and V = its Rec. 709 luminance ratio, as `wedges`.
/// `prepared`: the casters' adjacency from the method's prepare() (wedge_pass::caster_meshes of a
/// scene with ctx.scene's meshes); built here when null.
Image<float> wedge_blend_visibility(const ShadowContext& ctx, WedgeBlendStats* stats = nullptr,
                                    WedgeConstruction construction = WedgeConstruction::paper,
                                    Image<Vec3>* lit_rgb = nullptr, bool alpha_stsv = true,
                                    const wedge_pass::CasterMeshes* prepared = nullptr,
                                    const WedgeBlendPass2& pass2 = {});

/// The `wedge_blend` method with its per-pixel pass replaced by `pass2` (see WedgeBlendPass2).
std::unique_ptr<ShadowMethod> make_wedge_blend(const MethodOptions& options, WedgeBlendPass2 pass2);

}  // namespace penumbra
