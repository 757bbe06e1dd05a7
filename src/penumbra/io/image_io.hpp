// Image files: 8-bit sRGB PNG for viewing, float EXR / PFM for exact data and comparisons.
// Every failure (missing file, malformed or truncated data, unsupported format, write error)
// throws penumbra::Error with a one-line message naming the file.
#pragma once

#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "penumbra/core/image.hpp"
#include "penumbra/core/math.hpp"

namespace penumbra {

/// One named float channel of a multi-channel image ("light0", "light0.R", "mask", ...).
struct FloatLayer {
  std::string name;
  Image<float> pixels;
};

/// A FloatLayer that refers to its pixels (kept alive by the caller) instead of holding a copy.
struct FloatLayerView {
  std::string name;
  const Image<float>* pixels;
};

/// Linear -> sRGB transfer function (IEC 61966-2-1, piecewise); input clamped to [0,1], NaN -> 0.
float linear_to_srgb(float linear);
/// Linear value -> 8-bit sRGB code (clamped, rounded to nearest).
uint8_t linear_to_srgb8(float linear);

/// Writes linear RGB as an 8-bit sRGB-encoded PNG.
void write_png_rgb(const std::filesystem::path& path, const Image<Vec3>& linear_rgb);
/// The same from rows: rows(y, out) writes row y's width linear RGB pixels to out (called on
/// several threads at once, rows in any order), so that no float image need be kept.
void write_png_rgb(const std::filesystem::path& path, int width, int height,
                   const std::function<void(int y, Vec3* out)>& rows);
/// Writes already-encoded 8-bit RGB bytes (row-major, top row first, 3 bytes per pixel) as PNG.
void write_png_rgb8(const std::filesystem::path& path, int width, int height,
                    const std::vector<uint8_t>& rgb);

/// Writes one 32-bit FLOAT channel per layer, channel name = layer name, ZIP compression (zlib
/// level 1). All layers must have the same non-zero size and distinct non-empty names.
void write_exr(const std::filesystem::path& path, const std::vector<FloatLayer>& layers);
/// The same, from layers that refer to their pixels.
void write_exr_views(const std::filesystem::path& path, const std::vector<FloatLayerView>& layers);
/// Reads every channel of a scanline or tiled EXR as float (HALF/UINT are converted), in file
/// order (OpenEXR stores channels sorted by name). Pixel (0,0) is the data window's top-left.
std::vector<FloatLayer> read_exr(const std::filesystem::path& path);

/// Writes a greyscale PFM ("Pf"), little endian, rows bottom-to-top as the format requires.
void write_pfm(const std::filesystem::path& path, const Image<float>& image);
/// Writes a colour PFM ("PF"), little endian.
void write_pfm(const std::filesystem::path& path, const Image<Vec3>& image);
/// Reads a PFM (either endianness) as layers: {"Y"} for "Pf", {"R","G","B"} for "PF".
/// The magnitude of the scale field is ignored (as most readers do); its sign gives the endianness.
std::vector<FloatLayer> read_pfm(const std::filesystem::path& path);

/// Reads a float image by extension (case-insensitive): ".exr" or ".pfm".
std::vector<FloatLayer> read_float_image(const std::filesystem::path& path);

}  // namespace penumbra
