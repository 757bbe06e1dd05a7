// Which pixels a light can light at all. Every method computes visibility only for "active"
// pixels; the frame driver gives background pixels 1 and back-facing pixels 0.
#pragma once

#include <cstdint>

#include "penumbra/core/image.hpp"

namespace penumbra {

struct GBuffer;
struct Light;

enum ReceiverClass : uint8_t {
  kBackground = 0,
  kBackFacing = 1,  // the whole light lies behind the surface's tangent plane: unlit, V = 0
  kActive = 2,      // some of the light is in front: the method computes V
};

/// Classifies each pixel against the light's bounding parallelogram (its four corners; the point
/// itself for a point light), seen from the pixel's shadow origin.
Image<uint8_t> classify_receivers(const GBuffer& gbuffer, const Light& light);

}  // namespace penumbra
