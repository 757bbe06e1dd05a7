#include "penumbra/pipeline/frame.hpp"

#include <chrono>
#include <cmath>

#include "penumbra/core/error.hpp"
#include "penumbra/core/parallel.hpp"
#include "penumbra/pipeline/shading.hpp"
#include "penumbra/render/receivers.hpp"

namespace penumbra {

Frame::Frame(const Scene& scene, const LightSampleSpec& samples)
    : scene_(&scene), embree_(std::make_unique<EmbreeScene>(scene)), samples_(samples) {
  const auto start = std::chrono::steady_clock::now();
  gbuffer_ = render_gbuffer(*embree_, scene.camera);
  gbuffer_ms_ = elapsed_ms(start);
  const auto classify_start = std::chrono::steady_clock::now();
  for (const Light& light : scene.lights) {
    receivers_.push_back(classify_receivers(gbuffer_, light));
    irradiance_.emplace_back(scene, light);
  }
  receivers_ms_ = elapsed_ms(classify_start);
  unshadowed_ = std::make_unique<UnshadowedCache>(scene.lights.size());
}

const Image<Vec3>& Frame::unshadowed(size_t light) const {
  std::call_once(unshadowed_->once.at(light), [&] {
    const auto start = std::chrono::steady_clock::now();
    Image<Vec3> e(gbuffer_.width, gbuffer_.height, Vec3(0.0f));
    irradiance_[light].fill(gbuffer_, receivers_[light], e);
    unshadowed_->images[light] = std::move(e);
    unshadowed_->ms[light] = elapsed_ms(start);
  });
  return unshadowed_->images[light];
}

double Frame::irradiance_ms() const {
  double sum = 0.0;
  for (double ms : unshadowed_->ms) sum += ms;
  return sum;
}

MethodResult Frame::run(const MethodInfo& info, const MethodOptions& options,
                        bool want_masks) const {
  MethodResult result;
  result.method = info.name;
  result.options = options;
  for (size_t l = 0; l < scene_->lights.size(); ++l) {
    const ShadowContext ctx{*scene_,           *embree_, gbuffer_,      static_cast<int>(l),
                            scene_->lights[l], samples_, receivers_[l], want_masks};
    std::unique_ptr<ShadowMethod> method = info.create(options);
    const auto start = std::chrono::steady_clock::now();
    Visibility vis = method->compute(ctx);
    result.total_ms += elapsed_ms(start);

    if (vis.lit.width() != gbuffer_.width || vis.lit.height() != gbuffer_.height)
      throw Error("method '" + info.name + "' returned an image of the wrong size");
    const Image<uint8_t>& classes = receivers_[l];
    for (size_t i = 0; i < vis.lit.size(); ++i) {
      if (classes[i] == kBackground) vis.lit[i] = 1.0f;
      if (classes[i] == kBackFacing) vis.lit[i] = 0.0f;
      if (!std::isfinite(vis.lit[i]))
        throw Error("method '" + info.name + "' produced a non-finite value at pixel " +
                    std::to_string(i));
      if (vis.lit_rgb) {
        Vec3& rgb = (*vis.lit_rgb)[i];
        if (classes[i] != kActive) rgb = Vec3(vis.lit[i]);
        if (!is_finite(rgb))
          throw Error("method '" + info.name + "' produced a non-finite colour at pixel " +
                      std::to_string(i));
      }
    }
    result.per_light.push_back(std::move(vis));
  }
  return result;
}

}  // namespace penumbra
