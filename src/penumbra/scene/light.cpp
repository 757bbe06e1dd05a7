#include "penumbra/scene/light.hpp"

#include <cmath>

namespace penumbra {

std::string_view to_string(LightShape shape) {
  switch (shape) {
    case LightShape::point:
      return "point";
    case LightShape::rect:
      return "rect";
    case LightShape::disk:
      return "disk";
    case LightShape::sphere:
      return "sphere";
  }
  return "?";
}

float Light::area() const {
  switch (shape) {
    case LightShape::point:
      return 0.0f;
    case LightShape::rect:
      return glm::length(glm::cross(edge_u, edge_v));
    case LightShape::disk:
      return static_cast<float>(kPi) * radius * radius;
    case LightShape::sphere:
      return 4.0f * static_cast<float>(kPi) * radius * radius;
  }
  return 0.0f;
}

bool LightFrame::emits(Vec2 light_uv) const {
  if (!round) return true;
  const Vec2 d = light_uv - Vec2(0.5f);
  return glm::dot(d, d) <= 0.25f;
}

float LightFrame::uv_area() const {
  return round ? static_cast<float>(kPi) * 0.25f : 1.0f;
}

namespace {

LightFrame disk_frame(const Vec3& center, const Vec3& unit_normal, float radius) {
  Vec3 t, b;
  orthonormal_basis(unit_normal, t, b);
  LightFrame f;
  // (t, b, n) is right-handed, so cross(edge_u, edge_v) points along the emit normal.
  f.edge_u = 2.0f * radius * t;
  f.edge_v = 2.0f * radius * b;
  f.corner = center - 0.5f * (f.edge_u + f.edge_v);
  f.emit_normal = unit_normal;
  f.round = true;
  return f;
}

}  // namespace

LightFrame light_frame(const Light& light, const Vec3& receiver_world_pos) {
  switch (light.shape) {
    case LightShape::rect: {
      LightFrame f;
      f.edge_u = light.edge_u;
      f.edge_v = light.edge_v;
      f.corner = light.center - 0.5f * (light.edge_u + light.edge_v);
      f.emit_normal = unit_vector(glm::cross(light.edge_u, light.edge_v));
      return f;
    }
    case LightShape::disk:
      return disk_frame(light.center, glm::normalize(light.normal), light.radius);
    case LightShape::sphere: {
      const Vec3 to_receiver = receiver_world_pos - light.center;
      const float d = glm::length(to_receiver);
      const Vec3 n = d > 0.0f ? to_receiver / d : Vec3(0.0f, -1.0f, 0.0f);
      const float r = light.radius;
      if (d <= r) return disk_frame(light.center, n, r);
      const float shift = r * r / d;
      return disk_frame(light.center + shift * n, n, r * std::sqrt(1.0f - (r / d) * (r / d)));
    }
    case LightShape::point: {
      LightFrame f;
      f.corner = light.center;
      const Vec3 to_receiver = receiver_world_pos - light.center;
      const float d = glm::length(to_receiver);
      f.emit_normal = d > 0.0f ? to_receiver / d : Vec3(0.0f, -1.0f, 0.0f);
      return f;
    }
  }
  return {};
}

}  // namespace penumbra
