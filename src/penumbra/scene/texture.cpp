#include "penumbra/scene/texture.hpp"

#include <cmath>

namespace penumbra {

Vec3 Texture::sample_rgb(Vec2 uv) const {
  int tx = 0, ty = 0;
  texel_index(uv, tx, ty);
  if (channels < 3) return Vec3(channel(tx, ty, 0));
  return Vec3(channel(tx, ty, 0), channel(tx, ty, 1), channel(tx, ty, 2));
}

}  // namespace penumbra
