#include "penumbra/scene/camera.hpp"

#include <cmath>

namespace penumbra {

Camera::RayBasis Camera::ray_basis() const {
  // The basis in double: validate_scene has checked it is well defined there at any scale.
  const DVec3 forward = glm::normalize(DVec3(target) - DVec3(position));
  const DVec3 right = glm::normalize(glm::cross(forward, DVec3(up)));
  RayBasis b;
  b.forward = Vec3(forward);
  b.right = Vec3(right);
  b.true_up = Vec3(glm::cross(right, forward));
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
