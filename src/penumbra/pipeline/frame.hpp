// One frame: the scene's BVH, the G-buffer, the receiver classes per light and the shared light
// samples, built once; then any number of methods run on it, each on every light.
#pragma once

#include <atomic>
#include <chrono>
#include <exception>
#include <functional>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
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
  /// `layers`, when given, is called once the BVH is built and returns the G-buffer's storage
  /// allocated beforehand (background_gbuffer of the camera's size; gbuffer_ms then counts the
  /// wait for it, not its allocation).
  Frame(const Scene& scene, const LightSampleSpec& samples,
        const std::function<GBuffer()>& layers = {});
  /// The same on a BVH built before from a scene with the same meshes and materials (only the
  /// lights or the camera differ, as in `penumbra view`): the BVH is not built again.
  Frame(const Scene& scene, const LightSampleSpec& samples,
        std::shared_ptr<const EmbreeScene> embree);
  // Not movable: the background thread (start_unshadowed_in_background) holds `this`.
  Frame(Frame&&) = delete;
  Frame& operator=(Frame&&) = delete;

  const Scene& scene() const { return *scene_; }
  const EmbreeScene& embree() const { return *embree_; }
  /// The BVH, for another frame of the same scene (other samples, lights or camera).
  std::shared_ptr<const EmbreeScene> embree_shared() const { return embree_; }
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
  /// it. Thread-safe. Its rows are handed out one at a time to whichever thread asks: the
  /// background thread's (below) and then all cores here, so the image is the same however they
  /// were shared.
  const Image<Vec3>& unshadowed(size_t light) const;

  /// Starts computing unshadowed() of every light on one thread of the lowest priority (Linux's
  /// SCHED_IDLE): it takes rows while a core would otherwise idle, as in a method's serial stages,
  /// and gives its core up as soon as a method's thread wants it, so the methods' own times are
  /// not lengthened. unshadowed() then computes the rows it has not reached. Call once, before any
  /// unshadowed(); without it (or where the thread's priority cannot be lowered) unshadowed()
  /// computes every row.
  void start_unshadowed_in_background() const;
  /// Wall time from start_unshadowed_in_background to the background thread's last row, and the
  /// rows it computed (all lights).
  double irradiance_background_ms() const;
  int irradiance_background_rows() const;

 private:
  Frame(const Scene& scene, const LightSampleSpec& samples,
        std::shared_ptr<const EmbreeScene> embree, const std::function<GBuffer()>& layers);
  struct UnshadowedLight {
    std::once_flag once;
    Image<Vec3> image;
    std::atomic<int> next_row{0};   // rows handed out
    std::atomic<int> rows_done{0};  // rows written
    double ms = 0.0;                // unshadowed()'s own wall time
    std::exception_ptr error;       // the background thread's, set before its row counts as done
  };
  struct UnshadowedCache {
    explicit UnshadowedCache(size_t lights) : lights(lights) {}
    ~UnshadowedCache();  // stops the background thread after its current row
    std::vector<UnshadowedLight> lights;
    std::thread background;
    std::atomic<bool> stop{false};
    std::atomic<int> background_rows{0};
    std::atomic<double> background_ms{0.0};
  };
  /// Computes rows of `light` handed out from its next_row until none is left.
  void fill_unshadowed_rows(size_t light) const;
  /// The background thread's work: every light's rows, in order.
  void fill_unshadowed_in_background(std::chrono::steady_clock::time_point start) const;

  const Scene* scene_;
  std::shared_ptr<const EmbreeScene> embree_;
  GBuffer gbuffer_;
  LightSamples samples_;
  std::vector<Image<uint8_t>> receivers_;
  double gbuffer_ms_ = 0.0;
  double receivers_ms_ = 0.0;
  std::vector<LightIrradiance> irradiance_;
  std::unique_ptr<UnshadowedCache> unshadowed_;
};

}  // namespace penumbra
