// The STSV pass of the penumbra-wedge methods [Forest 2008 §5.2.1, Algorithm 12 lines 12–14]:
// `wedges` and `wedge_blend` compute a V_coef for the common meshes; the S-triangles add a
// per-pixel light-sample bitmask (LS_buffer), each S-triangle holding the pixel OR-ing in the
// samples behind its opaque texels (wedges/stsv_lookup.hpp). Its occluded fraction (the STSV
// V_coef, emission-weighted per channel for a textured light) is then added to the wedges'
// occlusion: V = clamp(V_wedges − occluded_stsv, 0, 1).
//
// Among S-triangles the bitmask is exact per sample (no underestimation where they overlap), but
// the sum with the wedges' V_coef counts twice the light that an S-triangle and a common mesh
// both block: the shadow overlapping artifact of fig. 5.4(a), measured in docs/methods/stsv.md.
// A semi-opaque textured material multiplies the sample by its transmittance instead of clearing
// it (the LS_buffer then holds the transmitted fraction per sample).
#pragma once

#include "penumbra/core/image.hpp"
#include "penumbra/shadows/method.hpp"
#include "penumbra/shadows/wedges/pass.hpp"
#include "penumbra/shadows/wedges/stsv.hpp"

namespace penumbra::stsv {

/// Builds the volumes of `perforated`, runs the bitmask pass and subtracts its occluded fraction
/// from `vis` (every kActive pixel) and, for a textured light, per channel from `lit_rgb` (when not
/// null). Returns what the method reports.
Summary subtract_stsv_occlusion(const ShadowContext& ctx, const wedge_pass::PixelSetup& setup,
                                Perforated perforated, Image<float>& vis, Image<Vec3>* lit_rgb);

}  // namespace penumbra::stsv
