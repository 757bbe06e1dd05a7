// The report's pictures: error maps on one common scale (absolute and signed), the window of a
// frame with the most penumbra, and nearest-neighbour crops of it.
#pragma once

#include <array>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "penumbra/core/image.hpp"
#include "penumbra/core/math.hpp"

namespace penumbra::report {

/// An 8-bit sRGB picture, row 0 at the top.
using Rgb8Image = Image<std::array<uint8_t, 3>>;

/// |V − V_exact| in viridis (0 → dark purple, >= scale → yellow); masked pixels dark grey.
Rgb8Image abs_error_picture(const Image<float>& signed_error, const Image<float>& mask,
                            double scale);
/// V − V_exact in a diverging map: blue = too dark (V < V_exact), red = too bright, white = 0,
/// saturating at ±scale; masked pixels dark grey.
Rgb8Image signed_error_picture(const Image<float>& signed_error, const Image<float>& mask,
                               double scale);
/// Linear RGB → 8-bit sRGB.
Rgb8Image srgb_picture(const Image<Vec3>& linear_rgb);

/// The colour stops (as "#rrggbb") of the two error maps, for their legends.
std::vector<std::string> abs_error_colors();
std::vector<std::string> signed_error_colors();

/// One scale for every method's error map of a frame: the median over the methods of each one's
/// 99th percentile of visible errors (|e| > 1/1024), rounded up to 1, 2 or 5 × 10^k and clamped
/// to [1/255, 1]. A shared maximum — or a pooled percentile — would let the worst method
/// flatten every other map; with the median, the worse half saturates instead.
double common_error_scale(const std::vector<const Image<float>*>& signed_errors,
                          const Image<float>& mask);

struct CropRect {
  int x = 0, y = 0, size = 0;
};

/// The square window (side min(w, h) / 4, at least 8) holding the most penumbra pixels of the
/// reference visibility (mask > 0.5 and 0.02 < V < 0.98); the image centre if there are none.
CropRect penumbra_window(const Image<float>& reference_v, const Image<float>& mask);

/// The window cut out of `picture` and enlarged `zoom` times (nearest neighbour, so pixels stay
/// visible as pixels).
Rgb8Image crop_zoom(const Rgb8Image& picture, const CropRect& rect, int zoom);

/// Writes the picture as a PNG (throws Error when it cannot).
void write_picture(const std::filesystem::path& path, const Rgb8Image& picture);

}  // namespace penumbra::report
