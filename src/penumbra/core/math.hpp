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

/// `v` made unit length in double, so that neither a tiny (1e-20) nor a huge (1e20) vector
/// underflows or overflows its squared length; (0, 0, 0) for a zero or non-finite vector.
inline Vec3 unit_vector(const Vec3& v) {
  const DVec3 d(v);
  const double len = glm::length(d);
  return len > 0.0 && std::isfinite(len) ? Vec3(d / len) : Vec3(0.0f);
}

/// Unit normal of triangle (a, b, c), counter-clockwise, computed in double (see unit_vector).
inline Vec3 triangle_normal(const Vec3& a, const Vec3& b, const Vec3& c) {
  const DVec3 n = glm::cross(DVec3(b) - DVec3(a), DVec3(c) - DVec3(a));
  const double len = glm::length(n);
  return len > 0.0 && std::isfinite(len) ? Vec3(n / len) : Vec3(0.0f);
}

/// |a × b| / (|a| |b|) in double, 0 when either is zero or not finite: the sine of the angle
/// between two directions, independent of their lengths (relative, so it holds at any scale).
inline double sine_between(const DVec3& a, const DVec3& b) {
  const double la = glm::length(a), lb = glm::length(b);
  if (!(la > 0.0) || !(lb > 0.0) || !std::isfinite(la) || !std::isfinite(lb)) return 0.0;
  return glm::length(glm::cross(a / la, b / lb));
}

/// Directions closer than this (sine of their angle) count as parallel — the camera's view and
/// up, a rectangle light's edges: float rounding would dominate their cross product.
inline constexpr double kParallelSine = 1e-6;

/// Any unit vector orthogonal to the unit vector n (Duff et al. 2017, branchless ONB).
inline void orthonormal_basis(const Vec3& n, Vec3& t, Vec3& b) {
  const float sign = std::copysign(1.0f, n.z);
  const float a = -1.0f / (sign + n.z);
  const float c = n.x * n.y * a;
  t = Vec3(1.0f + sign * n.x * n.x * a, sign * c, -sign * n.x);
  b = Vec3(c, sign + n.y * n.y * a, -n.y);
}

}  // namespace penumbra
