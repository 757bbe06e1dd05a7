// Lambertian direct light from every area light plus ambient, in linear float RGB.
#pragma once

#include <string_view>
#include <vector>

#include "penumbra/core/image.hpp"
#include "penumbra/core/math.hpp"
#include "penumbra/render/visibility.hpp"

namespace penumbra {

class Frame;

enum class ShadingMode {
  /// Direct light = unshadowed irradiance × V_coef (Forest 2008 eq. 4.3): works with every
  /// method.
  modulate,
  /// Direct light = Σ over light samples of visibility × radiance × geometry term (Forest 2008
  /// eq. 4.6):
  /// needs per-sample masks; lights without masks fall back to `modulate`.
  integrate,
};

std::string_view to_string(ShadingMode mode);

/// Shades every pixel. `per_light[l]` is the visibility of light l.
Image<Vec3> shade(const Frame& frame, const std::vector<const Visibility*>& per_light,
                  ShadingMode mode);

/// shade()'s pixels a row at a time, for a consumer that needs no whole image (the beauty PNG:
/// its 12 bytes a pixel never allocated). Thread-safe: rows in any order, on any threads.
class RowShader {
 public:
  RowShader(const Frame& frame, const std::vector<const Visibility*>& per_light, ShadingMode mode);
  /// Row y of shade()'s image into out[0, width).
  void row(int y, Vec3* out) const;

 private:
  const Frame* frame_;
  std::vector<const Visibility*> per_light_;
  ShadingMode mode_;
  float exposure_;
  std::vector<const Image<Vec3>*> unshadowed_;
};

/// A scale that maps the frame's unshadowed brightness to display range: the same for every method
/// of a frame, so their pictures compare.
float auto_exposure(const Frame& frame);

}  // namespace penumbra
