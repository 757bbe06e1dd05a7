// The active pixels as the wedge methods' pass 2 reads them on Vulkan (`wedges`, `wedge_blend`):
// per pixel what wedge_pass::PixelLight holds, in the layout of shaders/wedge_coverage.glsl.
#pragma once

#include <cstdint>
#include <vector>

#include "penumbra/shadows/method.hpp"

namespace penumbra::gpu {

/// wedge_coverage.glsl WedgePixel (scalar layout): the shadow origin, the light projection seen
/// from it, 1 / its light frame's uv area, its screen tile, flags (dcs.glsl kValid, kRound,
/// kTauNeg) and its pixel index.
struct WedgePixelGpu {
  double p[3], to_u[3], to_v[3], to_w[3];
  double inv_area;
  uint32_t tile, flags, pixel, pad;
};
static_assert(sizeof(WedgePixelGpu) == 120);

/// The kActive pixels of ctx in pixel order, for (sub-)light `light` and tiles `tiles_x` wide.
std::vector<WedgePixelGpu> wedge_pixels(const ShadowContext& ctx, const Light& light, int tiles_x);

}  // namespace penumbra::gpu
