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
};

}  // namespace penumbra
