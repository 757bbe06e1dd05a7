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

/// The tie rule for points on occluder planes, shared by every method (docs/architecture.md,
/// "Points on occluder planes"): an occluder blocks the shadow segment from a shadow origin o to a
/// light point L only where it crosses it at a segment parameter t ≤ kShadowSegmentEnd, i.e. the
/// segment's light end is offset like its receiver end. So a face through the light point (a
/// light centre on a box's face, a receiver or an occluder coplanar with the light) never blocks
/// it, whatever the rounding of the intersection: `raytrace` ends its rays there, `gears` moves
/// its plane line, `exact` clips occluders to W ≤ kShadowSegmentEnd, and `shadow_volume` skips the
/// faces whose plane holds the light point (face_side = 0, in double). 2⁻¹⁶ is far above float
/// rounding of t (≈ 1e-7) and exactly representable in float.
inline constexpr double kShadowSegmentEnd = 1.0 - 1.0 / 65536.0;

struct ShadowContext {
  const Scene& scene;
  /// The scene's Embree BVH, for the methods that trace rays through it (`raytrace`); others
  /// never read it, and a caller with its own G-buffer may leave it null for them.
  const EmbreeScene* embree;
  const GBuffer& gbuffer;
  int light_index = 0;
  const Light& light;
  const LightSamples& samples;      // the light samples every sampling method must use
  const Image<uint8_t>& receivers;  // ReceiverClass per pixel; compute only kActive pixels
  bool want_masks = false;          // sample-exact methods also fill Visibility::masks
};

/// A method's lifecycle: created with its options, prepare() once per scene (what depends on the
/// meshes and materials alone), then compute() any number of times, per frame and light (what
/// depends on the camera, the lights and the samples). A light that moves or a camera that turns
/// reuses everything prepared; a change of meshes or materials needs a new prepare().
class ShadowMethod {
 public:
  virtual ~ShadowMethod() = default;
  /// Scene-static work; `scene` outlives every compute() that follows. Default: nothing (the
  /// method does all its work in compute()).
  virtual void prepare(const Scene& scene) { (void)scene; }
  /// Visibility of ctx.light for every kActive pixel. Other pixels may hold anything: the frame
  /// driver overwrites them (background 1, back-facing 0). ctx.scene has the meshes and materials
  /// of the last prepare()'s scene (its lights and camera may differ).
  virtual Visibility compute(const ShadowContext& ctx) = 0;
};

}  // namespace penumbra
