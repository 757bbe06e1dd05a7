// Single- or multi-channel float textures (alpha masks, light emission), nearest-texel lookup.
#pragma once

#include <string>
#include <vector>

#include "penumbra/core/math.hpp"

namespace penumbra {

/// Row-major texels, row 0 at v = 0. Lookups wrap (repeat) and use the nearest texel: every method
/// and both references read a texture through texel_index(), so they agree texel for texel.
struct Texture {
  std::string name;
  int width = 0;
  int height = 0;
  int channels = 1;
  std::vector<float> texels;  // width * height * channels, linear values

  /// Texel column/row of texture coordinate `uv` (repeat wrap, nearest).
  void texel_index(Vec2 uv, int& tx, int& ty) const;
  float channel(int tx, int ty, int c) const {
    return texels[(static_cast<size_t>(ty) * width + tx) * channels + c];
  }
  /// First channel at uv (an alpha texture's value).
  float sample_scalar(Vec2 uv) const;
  /// RGB at uv (a one-channel texture is grey).
  Vec3 sample_rgb(Vec2 uv) const;
};

}  // namespace penumbra
