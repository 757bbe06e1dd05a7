// One frame: the scene's BVH, the G-buffer, the receiver classes per light and the shared light
// samples, built once; then any number of methods run on it, each on every light.
#pragma once

#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "penumbra/core/light_samples.hpp"
#include "penumbra/pipeline/irradiance.hpp"
#include "penumbra/render/embree_scene.hpp"
#include "penumbra/render/gbuffer.hpp"
#include "penumbra/shadows/registry.hpp"

namespace penumbra {

/// A method's answer for every light of the frame.
struct MethodResult {
  std::string method;
  MethodOptions options;
  std::vector<Visibility> per_light;
  double total_ms = 0.0;  // all lights, method time only (not the shared G-buffer)
};

class Frame {
 public:
  Frame(const Scene& scene, const LightSampleSpec& samples);

  const Scene& scene() const { return *scene_; }
  const EmbreeScene& embree() const { return *embree_; }
  const GBuffer& gbuffer() const { return gbuffer_; }
  const LightSamples& samples() const { return samples_; }
  const Image<uint8_t>& receivers(size_t light) const { return receivers_[light]; }
  double gbuffer_ms() const { return gbuffer_ms_; }
  /// Receiver classification, all lights.
  double receivers_ms() const { return receivers_ms_; }
  /// The unshadowed irradiance images computed so far (all lights; 0 until the first unshadowed()).
  double irradiance_ms() const;

  /// Runs `info` with `options` on every light. Pixels the method need not compute are set here:
  /// background 1, back-facing 0. Throws Error if the method returns a wrongly sized image, and
  /// replaces any non-finite value by failing loudly (never a NaN pixel in an output).
  MethodResult run(const MethodInfo& info, const MethodOptions& options, bool want_masks) const;

  /// The unshadowed irradiance of light `light` at every kActive pixel (0 elsewhere), at
  /// GBuffer::shadow_origin with the shading normal, in closed form (irradiance.hpp), computed on
  /// first use and kept: it does not depend on the method, so every method's beauty image shares
  /// it. Thread-safe.
  const Image<Vec3>& unshadowed(size_t light) const;

 private:
  struct UnshadowedCache {
    explicit UnshadowedCache(size_t lights) : once(lights), images(lights), ms(lights, 0.0) {}
    std::vector<std::once_flag> once;
    std::vector<Image<Vec3>> images;
    std::vector<double> ms;
  };

  const Scene* scene_;
  std::unique_ptr<EmbreeScene> embree_;
  GBuffer gbuffer_;
  LightSamples samples_;
  std::vector<Image<uint8_t>> receivers_;
  double gbuffer_ms_ = 0.0;
  double receivers_ms_ = 0.0;
  std::vector<LightIrradiance> irradiance_;
  std::unique_ptr<UnshadowedCache> unshadowed_;
};

}  // namespace penumbra
