// LightSamples: the one provider of light sample positions for every sampling method
// (raytrace, DCS, GEARS, STSV, ...). Positions are in light uv space [0,1)² of the light's
// LightFrame, so the same pattern gives the same world points to every method — two methods given
// the same LightSamples can agree sample by sample.
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <string_view>
#include <vector>

#include "penumbra/core/math.hpp"

namespace penumbra {

enum class SamplePattern {
  grid,          // regular k×k grid of cell centres (GEARS's bitmask layout)
  stratified,    // one jittered sample per cell of the k×k grid, same for every pixel
  decorrelated,  // the stratified pattern with a per-pixel random toroidal shift (Forest 2008
                 // §4.2.1)
  interleaved,   // n×n different stratified patterns tiled over the screen (Forest 2008 §4.2.2)
  halton,        // low-discrepancy Halton (2, 3) sequence, same for every pixel
  poisson,       // Poisson-disk (best-candidate) points on the torus, same for every pixel
};

std::string_view to_string(SamplePattern pattern);
std::optional<SamplePattern> parse_sample_pattern(std::string_view name);
const std::vector<SamplePattern>& all_sample_patterns();

struct LightSampleSpec {
  SamplePattern pattern = SamplePattern::grid;
  int k = 16;            // k×k samples per pixel; k = 1 with `grid` is the light centre
  uint64_t seed = 1;     // every random pattern is a pure function of (seed, pixel)
  int interleave_n = 4;  // `interleaved`: n×n distinct patterns
};

class LightSamples {
 public:
  explicit LightSamples(const LightSampleSpec& spec);

  const LightSampleSpec& spec() const { return spec_; }
  int k() const { return spec_.k; }
  int count() const { return spec_.k * spec_.k; }
  /// True when the positions depend on the pixel (decorrelated, interleaved).
  bool per_pixel() const;
  /// Writes the count() positions for pixel (x, y) into `light_uv` (size >= count()).
  /// Sample i of the grid-based patterns lies in cell (i % k, i / k): row-major, u fastest.
  void pixel_samples(int x, int y, std::span<Vec2> light_uv) const;
  /// The pixel-independent positions (empty when per_pixel()).
  std::span<const Vec2> shared_samples() const;

 private:
  LightSampleSpec spec_;
  std::vector<Vec2> shared_;  // grid, stratified, halton, poisson; base for decorrelated
  std::vector<std::vector<Vec2>> interleaved_;  // interleave_n² patterns
};

}  // namespace penumbra
