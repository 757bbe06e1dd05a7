// Single- or multi-channel float textures (alpha masks, light emission), nearest-texel lookup.
#pragma once

#include <algorithm>
#include <cmath>
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

  /// Texel column/row of texture coordinate `uv` (repeat wrap, nearest). Inline: the per-sample
  /// alpha lookups of the textured shadow volumes (shadows/wedges/stsv_lookup.hpp) call it in
  /// their inner loop.
  void texel_index(Vec2 uv, int& tx, int& ty) const {
    const float u = uv.x - std::floor(uv.x);
    const float v = uv.y - std::floor(uv.y);
    tx = std::min(width - 1, std::max(0, static_cast<int>(u * static_cast<float>(width))));
    ty = std::min(height - 1, std::max(0, static_cast<int>(v * static_cast<float>(height))));
  }
  float channel(int tx, int ty, int c) const {
    return texels[(static_cast<size_t>(ty) * width + tx) * channels + c];
  }
  /// First channel at uv (an alpha texture's value).
  float sample_scalar(Vec2 uv) const {
    int tx = 0, ty = 0;
    texel_index(uv, tx, ty);
    return channel(tx, ty, 0);
  }
  /// RGB at uv (a one-channel texture is grey).
  Vec3 sample_rgb(Vec2 uv) const;
};

}  // namespace penumbra
