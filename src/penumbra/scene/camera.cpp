#include "penumbra/scene/camera.hpp"

#include <cmath>

namespace penumbra {

Vec3 Camera::ray_direction(float x, float y) const {
  // The basis in double: validate_scene has checked it is well defined there at any scale.
  const DVec3 forward_d = glm::normalize(DVec3(target) - DVec3(position));
  const DVec3 right_d = glm::normalize(glm::cross(forward_d, DVec3(up)));
  const Vec3 forward(forward_d), right(right_d), true_up(glm::cross(right_d, forward_d));
  const float tan_half = std::tan(0.5f * vfov_deg * static_cast<float>(kPi) / 180.0f);
  const float aspect = static_cast<float>(width) / static_cast<float>(height);
  const float ndc_x = (2.0f * (x + 0.5f) / static_cast<float>(width) - 1.0f) * tan_half * aspect;
  const float ndc_y = (1.0f - 2.0f * (y + 0.5f) / static_cast<float>(height)) * tan_half;
  return glm::normalize(forward + ndc_x * right + ndc_y * true_up);
}

}  // namespace penumbra
