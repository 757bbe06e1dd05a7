// `shadow_map` (and the helpers `pcss` shares): hard shadows from a light-space depth map rendered
// from the light centre [Forest 2008 §2.2.2; Valient 2005 §1], with constant and
// slope-scaled depth bias and percentage-closer filtering (Reeves 1987).
//
// Depth comparison (the same in shadow_map and pcss): a tap at texel (i, j) is blocked iff the
// stored caster depth is smaller than the depth, at that texel's centre ray, of the receiver's
// tangent plane (through the shadow origin, normal = G-buffer geometric normal) minus the bias.
// Comparing against the receiver plane at each tap ("receiver-plane depth bias") instead of the
// receiver's own depth removes the acne planar receivers otherwise get from depth quantization and
// from wide filter kernels; the slope-scaled term (in texels of slope) covers curved receivers.
#pragma once

#include <string>
#include <vector>

#include "penumbra/raster/depth_map.hpp"
#include "penumbra/shadows/method.hpp"
#include "penumbra/shadows/registry.hpp"

namespace penumbra {

FaceSelect parse_face_select(const std::string& name);

/// The depth-map settings shadow_map and pcss share, declared once: resolution, faces, bias,
/// slope_bias.
std::vector<OptionSpec> depth_map_option_specs();
struct DepthMapSettings {
  int resolution = 2048;
  FaceSelect faces = FaceSelect::front;
  double bias = 0.0;        // constant, world units
  double slope_bias = 0.5;  // texels of depth slope

  static DepthMapSettings from(const MethodOptions& options);
  /// The receiver-fitted depth map from the light centre (hard_shadow_point) with these settings;
  /// its time goes to the stage "depth_map" of `times`.
  DepthMap render_from_light_centre(const ShadowContext& ctx, StageTimes& times) const;
};

/// The depth map of ctx's casters from `light_point`, its frustum fitted to the shadow origins of
/// the kActive pixels (every lookup lands in the map; a caster outside it cannot shadow them).
DepthMap receiver_fitted_depth_map(const ShadowContext& ctx, const Vec3& light_point,
                                   int resolution, FaceSelect faces);

/// PCSS's w_light: the rectangle's longer side, a disk's or sphere's diameter, 0 for a point.
double pcss_light_width(const Light& light);

/// Depth tests of one receiver point against a depth map.
class ShadowMapLookup {
 public:
  ShadowMapLookup(const DepthMap& map, double bias_constant, double bias_slope)
      : map_(map), bias_constant_(bias_constant), bias_slope_(bias_slope) {}

  /// Prepares the tests for shadow origin `p` with unit normal `n`; false if p is not in front of
  /// the light (then it is treated as lit).
  bool setup(const DVec3& p, const DVec3& n);
  /// Map position (texels) and view depth of p.
  double sx() const { return sx_; }
  double sy() const { return sy_; }
  double depth() const { return depth_; }
  /// Is the tap at texel (i, j) blocked? Outside the map: never.
  bool blocked(int i, int j) const;
  /// Stored caster depth at (i, j) if it blocks, else +inf.
  float blocker_depth(int i, int j) const;

 private:
  double plane_depth(int i, int j) const;

  const DepthMap& map_;
  double bias_constant_, bias_slope_;
  double sx_ = 0.0, sy_ = 0.0, depth_ = 0.0, bias_ = 0.0, plane_num_ = 0.0;
  double den0_ = 0.0, den_di_ = 0.0, den_dj_ = 0.0;  // n · direction(i + ½, j + ½), affine
};

}  // namespace penumbra
