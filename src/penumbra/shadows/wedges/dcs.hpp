// `dcs`: depth complexity sampling [Forest 2008 ch. 4; Laine 2005, the offline method it derives
// from], on the CPU, per G-buffer pixel: the per-sample answer of `raytrace` without casting a ray.
//
// Per active pixel p and light sample s, a signed counter holds the depth complexity D(p, s), the
// number of occluding triangles between p and s:
//   1. initialised to the shadow-volume count from the light centre (§4.1.1: the constant of
//      integration, wedges/shadow_volume.hpp);
//   2. every penumbra wedge holding p (wedges/geometry.hpp, binned to screen tiles by
//      wedges/pass.hpp) projects its edge from p onto the light, clips it (Algorithm 7 lines 4–5)
//      and adds its multiplicity to the counters of the samples the projected edge covers, with
//      the sign of the half (outer +, inner −) it lies in (lines 7–11; wedges/dcs_counters.hpp);
//   3. V = 1 − mean over emitting samples of Sat(D) (eq. 4.1), luminance-weighted per texel for a
//      textured light (eq. 4.2, RGB, shadows/light_weights.hpp); blocked = D > 0 in the masks.
// The edges and their per-receiver weights (wedges/dcs_edges.hpp) make the sum exact for any mesh
// when silhouettes are taken w.r.t. the whole light (§4.1.4, option `silhouettes=light`).
//
// Semi-opaque occluders (§4.3.3, Algorithms 8–9): the casters are split into layer classes —
// opaque, and one class per transmittance t — each with its own counters and centre count; a
// sample's transmittance is Π t^D_t (the exact product, what `raytrace` multiplies), or with
// `semi_opaque=paper` the counter-packing approximation V_s = 1 − Sat(D + Σ (1 − t)·D_t)
// ("summing the occluders' percentage of opaqueness", exact for one semi-opaque layer).
//
// Perforated (alpha-textured) triangles [Forest 2008 §5.2.2, wedges/stsv.hpp]: they leave the
// edges and centre counts and become S-triangles; per pixel inside an S-triangle's soft textured
// shadow volume, each light sample whose segment crosses one of its opaque texels gets +1 in the
// counter of the triangle's class, so D stays the number of occluders crossed (option
// `alpha=opaque`: solid, counter `alpha_textured_as_opaque`).
//
// Not handled (documented in docs/methods/dcs.md): triangles that cross the light's own plane
// inside the light (their cut by that plane is not an edge, so no wedge carries it).
#pragma once

#include <cstdint>

#include "penumbra/shadows/method.hpp"
#include "penumbra/shadows/wedges/dcs_edges.hpp"
#include "penumbra/shadows/wedges/geometry.hpp"

namespace penumbra {

enum class DcsSemiOpaque : uint8_t { exact, paper };

struct DcsOptions {
  dcs::SilhouetteMode silhouettes = dcs::SilhouetteMode::light;
  WedgeConstruction construction = WedgeConstruction::paper;
  DcsSemiOpaque semi_opaque = DcsSemiOpaque::exact;
  bool alpha_stsv = true;  // perforated triangles through soft textured shadow volumes (ch. 5)
};

/// Visibility (lit, lit_rgb for a textured light, masks when ctx.want_masks), stage times and
/// counters of `dcs` for ctx.light.
/// `prepared`: the casters' adjacency from the method's prepare() (wedge_pass::caster_meshes of a
/// scene with ctx.scene's meshes); built here when null.
Visibility dcs_visibility(const ShadowContext& ctx, const DcsOptions& options,
                          const wedge_pass::CasterMeshes* prepared = nullptr);

}  // namespace penumbra
