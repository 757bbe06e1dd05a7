// What every shadow method returns: the visible fraction of one light per pixel, plus optional
// per-sample bits, coloured visibility, stage times and counters.
#pragma once

#include <cstdint>
#include <optional>
#include <vector>

#include "penumbra/core/image.hpp"
#include "penumbra/core/math.hpp"
#include "penumbra/core/stats.hpp"

namespace penumbra {

/// Per pixel, one bit per light sample: bit i set = sample i is blocked. Sample-exact methods
/// (raytrace, GEARS, DCS) fill it so they can be compared sample by sample. Samples a round light
/// does not emit from are never set.
class SampleMasks {
 public:
  SampleMasks() = default;
  SampleMasks(int width, int height, int samples_per_pixel)
      : width_(width),
        height_(height),
        samples_(samples_per_pixel),
        words_((samples_per_pixel + 63) / 64),
        bits_(static_cast<size_t>(width) * height * words_, 0) {}

  int width() const { return width_; }
  int height() const { return height_; }
  int samples_per_pixel() const { return samples_; }
  int words_per_pixel() const { return words_; }
  uint64_t* pixel(size_t pixel_index) { return bits_.data() + pixel_index * words_; }
  const uint64_t* pixel(size_t pixel_index) const { return bits_.data() + pixel_index * words_; }
  bool blocked(size_t pixel_index, int sample) const {
    return (pixel(pixel_index)[sample >> 6] >> (sample & 63)) & 1u;
  }
  void set_blocked(size_t pixel_index, int sample) {
    pixel(pixel_index)[sample >> 6] |= uint64_t{1} << (sample & 63);
  }

 private:
  int width_ = 0, height_ = 0, samples_ = 0, words_ = 0;
  std::vector<uint64_t> bits_;
};

struct Visibility {
  /// Fraction of the light visible from each pixel's point, 1 = fully lit. Background pixels
  /// hold 1, pixels facing away from the light 0 (see receivers.hpp).
  Image<float> lit;
  /// Visible fraction of a textured light's emitted RGB power (per channel); absent otherwise.
  std::optional<Image<Vec3>> lit_rgb;
  std::optional<SampleMasks> masks;
  StageTimes times;
  Counters counters;
};

}  // namespace penumbra
