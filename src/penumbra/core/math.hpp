// Vector types and small geometric helpers shared by every module.
#pragma once

#include <cmath>
#include <glm/glm.hpp>
#include <limits>

namespace penumbra {

using Vec2 = glm::vec2;
using Vec3 = glm::vec3;
using Vec4 = glm::vec4;
using DVec2 = glm::dvec2;
using DVec3 = glm::dvec3;
using Mat4 = glm::mat4;

inline constexpr float kInfinity = std::numeric_limits<float>::infinity();
inline constexpr double kPi = 3.14159265358979323846;

inline bool is_finite(const Vec3& v) {
  return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

/// Axis-aligned bounding box in world space.
struct Bounds3 {
  Vec3 lo{kInfinity};
  Vec3 hi{-kInfinity};

  void extend(const Vec3& p) {
    lo = glm::min(lo, p);
    hi = glm::max(hi, p);
  }
  void extend(const Bounds3& b) {
    lo = glm::min(lo, b.lo);
    hi = glm::max(hi, b.hi);
  }
  bool empty() const { return lo.x > hi.x; }
  Vec3 center() const { return 0.5f * (lo + hi); }
  Vec3 extent() const { return hi - lo; }
  float diagonal() const { return empty() ? 0.0f : glm::length(hi - lo); }
};

/// Any unit vector orthogonal to the unit vector n (Duff et al. 2017, branchless ONB).
inline void orthonormal_basis(const Vec3& n, Vec3& t, Vec3& b) {
  const float sign = std::copysign(1.0f, n.z);
  const float a = -1.0f / (sign + n.z);
  const float c = n.x * n.y * a;
  t = Vec3(1.0f + sign * n.x * n.x * a, sign * c, -sign * n.x);
  b = Vec3(c, sign + n.y * n.y * a, -n.y);
}

}  // namespace penumbra
