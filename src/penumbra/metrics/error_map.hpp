// False-colour rendering of a per-pixel error image, with a labelled colour-bar legend.
#pragma once

#include <array>
#include <cstdint>
#include <filesystem>
#include <string>

#include "penumbra/core/image.hpp"

namespace penumbra {

using Rgb8 = std::array<uint8_t, 3>;

/// Colour for pixels excluded by the mask.
inline constexpr Rgb8 kErrorMapMaskedColor{48, 48, 48};
/// Colour for NaN error values (flags a bug rather than hiding it).
inline constexpr Rgb8 kErrorMapNanColor{255, 0, 255};
/// Legend background and text colours.
inline constexpr Rgb8 kErrorMapLegendBackground{0, 0, 0};
inline constexpr Rgb8 kErrorMapLegendText{255, 255, 255};

/// Viridis colormap, approximated by 9 samples with linear interpolation; t clamped to [0,1].
Rgb8 error_colormap(double t);

/// Height in pixels of the legend strip appended below an image of this width
/// (text and bar are drawn twice as large when width >= 512).
int error_map_legend_height(int width);

/// Tick label for a legend value: the shortest %g form (2 to 6 significant digits) within 0.6%
/// of the value, e.g. 1/255 -> "0.0039", 0.5 -> "0.5", 0 -> "0".
std::string error_map_label(double value);

/// Writes `abs_error` in false colour (0 -> error_colormap(0), >= scale_max -> error_colormap(1)),
/// pixels with (*mask)(x,y) <= 0.5 in kErrorMapMaskedColor, with a legend strip (colour bar and
/// tick labels 0, scale_max/2, scale_max) appended at the bottom. The PNG is
/// width x (height + error_map_legend_height(width)). Throws Error on an empty image, a mask of
/// another size, a scale_max that is not finite and > 0, or a write failure.
void write_error_map_png(const std::filesystem::path& path, const Image<float>& abs_error,
                         double scale_max, const Image<float>* mask = nullptr);

}  // namespace penumbra
