// Random draws the seeded procedural scenes share (PCG32: the same numbers on every platform).
#pragma once

#include <algorithm>
#include <cmath>

#include "penumbra/core/math.hpp"
#include "penumbra/core/rng.hpp"

namespace penumbra {

/// Uniform in [lo, hi).
inline float uniform_in(Pcg32& rng, float lo, float hi) {
  return lo + (hi - lo) * rng.next_float();
}

/// Uniform on the unit sphere (Archimedes: y uniform in [-1, 1], azimuth uniform).
inline Vec3 random_direction(Pcg32& rng) {
  const float y = uniform_in(rng, -1.0f, 1.0f);
  const float phi = uniform_in(rng, 0.0f, 2.0f * static_cast<float>(kPi));
  const float r = std::sqrt(std::max(0.0f, 1.0f - y * y));
  return Vec3(r * std::cos(phi), y, r * std::sin(phi));
}

}  // namespace penumbra
