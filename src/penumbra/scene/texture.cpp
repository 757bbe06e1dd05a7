#include "penumbra/scene/texture.hpp"

#include <cmath>

namespace penumbra {

void Texture::texel_index(Vec2 uv, int& tx, int& ty) const {
  const float u = uv.x - std::floor(uv.x);
  const float v = uv.y - std::floor(uv.y);
  tx = std::min(width - 1, std::max(0, static_cast<int>(u * static_cast<float>(width))));
  ty = std::min(height - 1, std::max(0, static_cast<int>(v * static_cast<float>(height))));
}

float Texture::sample_scalar(Vec2 uv) const {
  int tx = 0, ty = 0;
  texel_index(uv, tx, ty);
  return channel(tx, ty, 0);
}

Vec3 Texture::sample_rgb(Vec2 uv) const {
  int tx = 0, ty = 0;
  texel_index(uv, tx, ty);
  if (channels < 3) return Vec3(channel(tx, ty, 0));
  return Vec3(channel(tx, ty, 0), channel(tx, ty, 1), channel(tx, ty, 2));
}

}  // namespace penumbra
