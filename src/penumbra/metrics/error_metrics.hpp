// Error statistics between a reference and a test visibility/shadow image (values in [0,1]).
#pragma once

#include <cstddef>
#include <nlohmann/json.hpp>

#include "penumbra/core/image.hpp"

namespace penumbra {

/// Statistics over the counted pixels (mask > 0.5, or all pixels without a mask).
struct ErrorStats {
  /// Mean |test - ref| over the counted pixels whose reference is shadowed or in penumbra
  /// (ref < 1 - kShadowedThreshold), as in Atty 2006 §4.2.1; 0 if there are none.
  double mean_abs_shadowed = 0.0;
  double mean_abs = 0.0;
  double rmse = 0.0;
  double max_abs = 0.0;
  /// 10 log10(1 / mse) with peak 1; kPsnrCap when mse == 0 (or no pixel counted).
  double psnr = 0.0;
  /// Fraction of counted pixels with |diff| > 1/255, resp. > 1/16.
  double frac_over_1_255 = 0.0;
  double frac_over_1_16 = 0.0;
  size_t pixels = 0;           ///< counted pixels
  size_t shadowed_pixels = 0;  ///< counted pixels with ref < 1 - kShadowedThreshold
};

/// A reference pixel counts as shadowed (umbra or penumbra) when ref < 1 - kShadowedThreshold.
inline constexpr double kShadowedThreshold = 1e-4;
/// PSNR reported for identical images (keeps JSON finite).
inline constexpr double kPsnrCap = 999.0;

/// Compares `test` against `ref`. Only pixels with (*mask)(x,y) > 0.5 count when a mask is given.
/// Throws Error on size mismatch (test or mask vs ref) and on a non-finite value (NaN/Inf) in
/// ref, test or mask, naming the image and pixel.
ErrorStats compare_images(const Image<float>& ref, const Image<float>& test,
                          const Image<float>* mask = nullptr);

/// JSON object with exactly the keys mean_abs_shadowed, mean_abs, rmse, max_abs, psnr,
/// frac_over_1_255, frac_over_1_16, pixels, shadowed_pixels.
nlohmann::json to_json(const ErrorStats& stats);

/// Per-pixel |test - ref|. Same checks (size, non-finite values) as compare_images.
Image<float> abs_difference(const Image<float>& ref, const Image<float>& test);

}  // namespace penumbra
