#include "penumbra/scene/camera.hpp"

#include <cmath>

namespace penumbra {

Vec3 Camera::ray_direction(float x, float y) const {
  const Vec3 forward = glm::normalize(target - position);
  const Vec3 right = glm::normalize(glm::cross(forward, up));
  const Vec3 true_up = glm::cross(right, forward);
  const float tan_half = std::tan(0.5f * vfov_deg * static_cast<float>(kPi) / 180.0f);
  const float aspect = static_cast<float>(width) / static_cast<float>(height);
  const float ndc_x = (2.0f * (x + 0.5f) / static_cast<float>(width) - 1.0f) * tan_half * aspect;
  const float ndc_y = (1.0f - 2.0f * (y + 0.5f) / static_cast<float>(height)) * tan_half;
  return glm::normalize(forward + ndc_x * right + ndc_y * true_up);
}

}  // namespace penumbra
