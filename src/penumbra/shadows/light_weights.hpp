// Turning per-sample visibility into a pixel's visible fraction, shared by every sampling method
// so that they weight samples identically: samples a round light does not emit from are skipped;
// a textured light weights each sample by its emitted radiance (nearest texel over light uv).
#pragma once

#include <span>

#include "penumbra/core/math.hpp"
#include "penumbra/scene/light.hpp"
#include "penumbra/scene/texture.hpp"

namespace penumbra {

/// Rec. 709 luminance: how a textured light's RGB visibility collapses to one V_coef.
inline float luminance(const Vec3& rgb) {
  return 0.2126f * rgb.x + 0.7152f * rgb.y + 0.0722f * rgb.z;
}

struct SampleWeights {
  Vec3 visible{0.0f};  // Σ visibility · weight
  Vec3 total{0.0f};    // Σ weight

  /// Luminance-weighted visible fraction (1 when no sample emits).
  float visible_fraction() const {
    const float t = luminance(total);
    return t > 0.0f ? std::min(1.0f, luminance(visible) / t) : 1.0f;
  }
  Vec3 visible_fraction_rgb() const {
    Vec3 out(1.0f);
    for (int c = 0; c < 3; ++c)
      if (total[c] > 0.0f) out[c] = std::min(1.0f, visible[c] / total[c]);
    return out;
  }
};

/// Σ over emitting samples of visibility × weight, weight = emission texture × radiance (textured
/// lights) or 1.
inline SampleWeights accumulate_sample_weights(const LightFrame& frame, const Texture* emission,
                                               const Vec3& radiance, std::span<const Vec2> light_uv,
                                               std::span<const float> sample_vis) {
  SampleWeights w;
  for (size_t s = 0; s < light_uv.size(); ++s) {
    if (!frame.emits(light_uv[s])) continue;
    const Vec3 weight = emission ? emission->sample_rgb(light_uv[s]) * radiance : Vec3(1.0f);
    w.visible += sample_vis[s] * weight;
    w.total += weight;
  }
  return w;
}

}  // namespace penumbra
