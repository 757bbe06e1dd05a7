// The shadow-method interface: every method reads one ShadowContext and returns one Visibility,
// so methods can be swapped, compared pixel by pixel and benchmarked by name.
#pragma once

#include <cstdint>

#include "penumbra/core/image.hpp"
#include "penumbra/core/light_samples.hpp"
#include "penumbra/render/gbuffer.hpp"
#include "penumbra/render/visibility.hpp"
#include "penumbra/scene/scene.hpp"

namespace penumbra {

class EmbreeScene;

struct ShadowContext {
  const Scene& scene;
  const EmbreeScene& embree;  // the scene's BVH (built once per frame)
  const GBuffer& gbuffer;
  int light_index = 0;
  const Light& light;
  const LightSamples& samples;      // the light samples every sampling method must use
  const Image<uint8_t>& receivers;  // ReceiverClass per pixel; compute only kActive pixels
  bool want_masks = false;          // sample-exact methods also fill Visibility::masks
};

class ShadowMethod {
 public:
  virtual ~ShadowMethod() = default;
  /// Visibility of ctx.light for every kActive pixel. Other pixels may hold anything: the frame
  /// driver overwrites them (background 1, back-facing 0).
  virtual Visibility compute(const ShadowContext& ctx) = 0;
};

}  // namespace penumbra
