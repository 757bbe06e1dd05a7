#include "penumbra/scene/camera.hpp"

#include <cmath>

namespace penumbra {

Camera::RayBasis Camera::ray_basis() const {
  RayBasis b;
  b.forward = glm::normalize(target - position);
  b.right = glm::normalize(glm::cross(b.forward, up));
  b.true_up = glm::cross(b.right, b.forward);
  b.tan_half = std::tan(0.5f * vfov_deg * static_cast<float>(kPi) / 180.0f);
  b.aspect = static_cast<float>(width) / static_cast<float>(height);
  b.width = width;
  b.height = height;
  return b;
}

Vec3 Camera::ray_direction(float x, float y) const {
  return ray_basis().direction(x, y);
}

}  // namespace penumbra
