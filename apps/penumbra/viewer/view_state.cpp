#include "view_state.hpp"

#include <algorithm>
#include <cmath>

#include "penumbra/core/error.hpp"

namespace penumbra::viewer {

namespace {

float radians(float deg) {
  return deg * static_cast<float>(kPi) / 180.0f;
}

/// Any unit vector normal to `n`.
Vec3 any_normal(const Vec3& n) {
  const Vec3 a = std::abs(n.x) < 0.9f ? Vec3(1.0f, 0.0f, 0.0f) : Vec3(0.0f, 1.0f, 0.0f);
  return glm::normalize(glm::cross(n, a));
}

}  // namespace

OrbitCamera::OrbitCamera(const Camera& base)
    : base_(base), target_(base.target), up_(glm::normalize(base.up)) {
  const Vec3 offset = base.position - base.target;
  distance_ = glm::length(offset);
  const Vec3 dir = offset / distance_;
  elevation_deg_ =
      std::asin(std::clamp(glm::dot(dir, up_), -1.0f, 1.0f)) * 180.0f / static_cast<float>(kPi);
  const Vec3 flat = dir - glm::dot(dir, up_) * up_;
  h0_ = glm::length(flat) > 1e-6f ? glm::normalize(flat) : any_normal(up_);
  h1_ = glm::cross(up_, h0_);
}

Camera OrbitCamera::camera() const {
  if (!moved_) return base_;
  Camera c = base_;
  const float az = radians(azimuth_deg_), el = radians(elevation_deg_);
  const Vec3 dir = std::cos(el) * (std::cos(az) * h0_ + std::sin(az) * h1_) + std::sin(el) * up_;
  c.target = target_;
  c.position = target_ + distance_ * dir;
  c.up = up_;
  return c;
}

void OrbitCamera::orbit(float d_azimuth_deg, float d_elevation_deg) {
  azimuth_deg_ = std::remainder(azimuth_deg_ + d_azimuth_deg, 360.0f);
  // Short of the poles, where the view direction would be parallel to the up axis.
  elevation_deg_ = std::clamp(elevation_deg_ + d_elevation_deg, -89.0f, 89.0f);
  moved_ = true;
}

void OrbitCamera::pan(float right_fraction, float up_fraction) {
  const Camera c = camera();
  const Vec3 forward = glm::normalize(c.target - c.position);
  const Vec3 right = glm::normalize(glm::cross(forward, up_));
  const Vec3 true_up = glm::cross(right, forward);
  target_ += distance_ * (right_fraction * right + up_fraction * true_up);
  moved_ = true;
}

void OrbitCamera::zoom(float factor) {
  if (factor > 0.0f && std::isfinite(factor)) distance_ = std::max(distance_ * factor, 1e-6f);
  moved_ = true;
}

Light edited_light(const Light& base, const LightEdit& edit) {
  Light l = base;
  l.center = edit.center;
  l.radiance = base.radiance * edit.intensity;
  // The direction the light emits toward, and the area it shows a receiver (a sphere its
  // silhouette disk's, not its surface's), whatever its shape.
  Vec3 normal = base.normal;
  float area = base.area();
  if (base.shape == LightShape::rect) normal = glm::normalize(glm::cross(base.edge_u, base.edge_v));
  if (base.shape == LightShape::sphere) area = static_cast<float>(kPi) * base.radius * base.radius;
  const float s = edit.scale;
  l.shape = edit.shape;
  if (edit.shape == base.shape) {
    l.edge_u = base.edge_u * s;
    l.edge_v = base.edge_v * s;
    l.radius = base.radius * s;
    return l;
  }
  const float side = area > 0.0f ? std::sqrt(area) : 0.1f;  // a point light: any small size
  switch (edit.shape) {
    case LightShape::rect: {
      const Vec3 u = any_normal(normal);
      l.edge_u = u * side * s;
      l.edge_v = glm::cross(normal, u) * side * s;  // cross(edge_u, edge_v) ∥ normal
      break;
    }
    case LightShape::disk:
    case LightShape::sphere:
      l.radius = side / std::sqrt(static_cast<float>(kPi)) * s;
      l.normal = normal;
      l.emission_texture = -1;
      break;
    case LightShape::point:
      l.emission_texture = -1;
      break;
  }
  return l;
}

ViewState::ViewState(const Scene& scene, std::string method_name, const LightSampleSpec& spec)
    : method(std::move(method_name)),
      camera(scene.camera),
      samples(spec),
      width(scene.camera.width),
      height(scene.camera.height) {
  for (const Light& l : scene.lights) lights.push_back({l.center, 1.0f, l.shape, 1.0f});
  time_s = scene.animation.start_s;
}

Scene edited_scene(const Scene& base, const std::vector<LightEdit>& lights, const Camera& camera,
                   double time_s, bool camera_moved) {
  const bool animated = !base.animation.empty();
  Scene scene = animated ? pose_scene(base, time_s) : base;
  for (size_t l = 0; l < scene.lights.size() && l < lights.size(); ++l) {
    LightEdit edit = lights[l];
    edit.center += scene.lights[l].center - base.lights[l].center;  // 0 for a still light
    scene.lights[l] = edited_light(scene.lights[l], edit);
  }
  if (animated && base.animation.moves_camera() && !camera_moved) {
    scene.camera.width = camera.width;
    scene.camera.height = camera.height;
  } else {
    scene.camera = camera;
  }
  validate_scene(scene);
  return scene;
}

}  // namespace penumbra::viewer
