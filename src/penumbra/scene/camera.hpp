// Pinhole camera: position/target/up, vertical field of view, resolution.
#pragma once

#include "penumbra/core/math.hpp"

namespace penumbra {

struct Camera {
  Vec3 position{0.0f, 1.0f, 3.0f};
  Vec3 target{0.0f};
  Vec3 up{0.0f, 1.0f, 0.0f};
  float vfov_deg = 45.0f;
  int width = 512;
  int height = 512;

  /// Unit world-space direction through the centre of pixel (x, y); row 0 is the top row.
  Vec3 ray_direction(float x, float y) const;

  /// The per-frame part of ray_direction, computed once (same floats, so the same directions).
  struct RayBasis {
    Vec3 forward, right, true_up;
    float tan_half = 0.0f, aspect = 1.0f;
    int width = 1, height = 1;
    Vec3 direction(float x, float y) const {
      const float ndc_x =
          (2.0f * (x + 0.5f) / static_cast<float>(width) - 1.0f) * tan_half * aspect;
      const float ndc_y = (1.0f - 2.0f * (y + 0.5f) / static_cast<float>(height)) * tan_half;
      return glm::normalize(forward + ndc_x * right + ndc_y * true_up);
    }
  };
  RayBasis ray_basis() const;
};

}  // namespace penumbra
