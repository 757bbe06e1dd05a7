// Surface materials: what a receiver reflects and how an occluder blocks light.
#pragma once

#include <string>

#include "penumbra/core/math.hpp"

namespace penumbra {

/// Texels with alpha below this are holes (perforated triangles). One cutoff for every method.
inline constexpr float kAlphaCutoff = 0.5f;

struct Material {
  std::string name;
  Vec3 albedo{0.8f};       // Lambertian reflectance, linear RGB
  int alpha_texture = -1;  // index into Scene::textures; -1 = fully opaque surface
  /// Fraction of light passing each crossing of this surface (0 = opaque, Forest 2008 §4.3.3
  /// semi-opaque occluders). Visibility through k crossings is transmittance^k.
  float transmittance = 0.0f;

  bool is_opaque() const { return alpha_texture < 0 && transmittance <= 0.0f; }
};

}  // namespace penumbra
