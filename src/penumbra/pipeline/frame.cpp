#include "penumbra/pipeline/frame.hpp"

#ifdef __linux__
#include <pthread.h>
#include <sched.h>
#endif
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <chrono>
#include <cmath>
#include <limits>
#include <utility>

#include "penumbra/core/error.hpp"
#include "penumbra/core/parallel.hpp"
#include "penumbra/pipeline/shading.hpp"
#include "penumbra/render/receivers.hpp"

namespace penumbra {

Frame::Frame(const Scene& scene, const LightSampleSpec& samples,
             const std::function<GBuffer()>& layers)
    : Frame(scene, samples, std::make_shared<const EmbreeScene>(scene), layers) {}

Frame::Frame(const Scene& scene, const LightSampleSpec& samples,
             std::shared_ptr<const EmbreeScene> embree)
    : Frame(scene, samples, std::move(embree), {}) {}

Frame::Frame(const Scene& scene, const LightSampleSpec& samples,
             std::shared_ptr<const EmbreeScene> embree, const std::function<GBuffer()>& layers)
    : scene_(&scene), embree_(std::move(embree)), samples_(samples) {
  const auto start = std::chrono::steady_clock::now();
  gbuffer_ = render_gbuffer(*embree_, scene.camera, layers ? layers() : GBuffer{});
  gbuffer_ms_ = elapsed_ms(start);
  const auto classify_start = std::chrono::steady_clock::now();
  for (const Light& light : scene.lights) {
    receivers_.push_back(classify_receivers(gbuffer_, light));
    irradiance_.emplace_back(scene, light);
  }
  receivers_ms_ = elapsed_ms(classify_start);
  unshadowed_ = std::make_unique<UnshadowedCache>(scene.lights.size());
}

Frame::UnshadowedCache::~UnshadowedCache() {
  stop = true;
  if (background.joinable()) background.join();
}

void Frame::fill_unshadowed_rows(size_t light) const {
  UnshadowedLight& u = unshadowed_->lights[light];
  const int height = gbuffer_.height;
  for (int y = u.next_row.fetch_add(1); y < height; y = u.next_row.fetch_add(1)) {
    irradiance_[light].fill_row(gbuffer_, receivers_[light], u.image, y);
    if (u.rows_done.fetch_add(1) + 1 == height) u.rows_done.notify_all();
  }
}

const Image<Vec3>& Frame::unshadowed(size_t light) const {
  UnshadowedLight& u = unshadowed_->lights.at(light);
  std::call_once(u.once, [&] {
    const auto start = std::chrono::steady_clock::now();
    if (u.image.empty()) u.image = Image<Vec3>(gbuffer_.width, gbuffer_.height, Vec3(0.0f));
    // One task per thread, each taking rows until none is left; then the background thread's
    // last row, if it is still computing one.
    tbb::parallel_for(0, tbb::this_task_arena::max_concurrency(),
                      [&](int) { fill_unshadowed_rows(light); });
    for (int done = u.rows_done.load(); done < gbuffer_.height; done = u.rows_done.load())
      u.rows_done.wait(done);
    if (u.error) std::rethrow_exception(u.error);
    u.ms += elapsed_ms(start);
  });
  return u.image;
}

void Frame::start_unshadowed_in_background() const {
  if (unshadowed_->background.joinable()) return;
  const auto start = std::chrono::steady_clock::now();
  // Allocated here, before the thread starts, so that both sides find the images in place (an
  // image unshadowed() already made is kept: its rows are all handed out).
  for (UnshadowedLight& u : unshadowed_->lights) {
    if (!u.image.empty()) continue;
    const auto light_start = std::chrono::steady_clock::now();
    u.image = Image<Vec3>(gbuffer_.width, gbuffer_.height, Vec3(0.0f));
    u.ms += elapsed_ms(light_start);
  }
  unshadowed_->background = std::thread([this, start] { fill_unshadowed_in_background(start); });
}

void Frame::fill_unshadowed_in_background(std::chrono::steady_clock::time_point start) const {
#ifdef __linux__
  // SCHED_IDLE, not nice 19: the scheduler preempts an idle-policy thread as soon as any other
  // thread wakes on its core (at nice 19 the method's threads measured ≈ 15% slower on a loaded
  // machine). Its share of a busy core is still not zero, so unshadowed()'s wait for the row it
  // is computing ends.
  const sched_param param{};
  if (::pthread_setschedparam(::pthread_self(), SCHED_IDLE, &param) != 0) return;
#else
  return;  // no per-thread priority: the methods would share their cores with this thread
#endif
  UnshadowedCache& cache = *unshadowed_;
  const int height = gbuffer_.height;
  for (size_t l = 0; l < cache.lights.size(); ++l) {
    UnshadowedLight& u = cache.lights[l];
    for (int y = u.next_row.fetch_add(1); y < height; y = u.next_row.fetch_add(1)) {
      if (!cache.stop) {
        try {
          irradiance_[l].fill_row(gbuffer_, receivers_[l], u.image, y);
        } catch (...) {
          u.error = std::current_exception();
          cache.stop = true;
        }
      }
      if (!cache.stop) {
        cache.background_rows.fetch_add(1);
        cache.background_ms = elapsed_ms(start);
      }
      // A row handed out is always counted, even after a stop or an error: unshadowed() waits
      // for the count (it rethrows the error).
      if (u.rows_done.fetch_add(1) + 1 == height) u.rows_done.notify_all();
      if (cache.stop) return;
    }
  }
}

double Frame::irradiance_ms() const {
  double sum = 0.0;
  for (const UnshadowedLight& u : unshadowed_->lights) sum += u.ms;
  return sum;
}

double Frame::irradiance_background_ms() const {
  return unshadowed_->background_ms;
}

int Frame::irradiance_background_rows() const {
  return unshadowed_->background_rows;
}

MethodResult Frame::run(const MethodInfo& info, const MethodOptions& options,
                        bool want_masks) const {
  const std::unique_ptr<ShadowMethod> method = info.create(options);
  const auto start = std::chrono::steady_clock::now();
  method->prepare(*scene_);
  const double prepare_ms = elapsed_ms(start);
  MethodResult result = run(info, *method, options, want_masks);
  result.prepare_ms = prepare_ms;
  result.total_ms += prepare_ms;
  return result;
}

MethodResult Frame::run(const MethodInfo& info, ShadowMethod& method, const MethodOptions& options,
                        bool want_masks) const {
  MethodResult result;
  result.method = info.name;
  result.options = options;
  for (size_t l = 0; l < scene_->lights.size(); ++l) {
    const ShadowContext ctx{*scene_,           embree_.get(), gbuffer_,      static_cast<int>(l),
                            scene_->lights[l], samples_,      receivers_[l], want_masks};
    const auto start = std::chrono::steady_clock::now();
    Visibility vis = method.compute(ctx);
    result.total_ms += elapsed_ms(start);

    if (vis.lit.width() != gbuffer_.width || vis.lit.height() != gbuffer_.height)
      throw Error("method '" + info.name + "' returned an image of the wrong size");
    const Image<uint8_t>& classes = receivers_[l];
    // In parallel chunks; the first non-finite pixel is the one reported, as by a serial pass.
    constexpr size_t kNone = std::numeric_limits<size_t>::max();
    std::atomic<size_t> first_bad{kNone};
    parallel_chunks(vis.lit.size(), size_t{1} << 16, [&](size_t begin, size_t end) {
      for (size_t i = begin; i < end; ++i) {
        if (classes[i] == kBackground) vis.lit[i] = 1.0f;
        if (classes[i] == kBackFacing) vis.lit[i] = 0.0f;
        bool finite = std::isfinite(vis.lit[i]);
        if (finite && vis.lit_rgb) {
          Vec3& rgb = (*vis.lit_rgb)[i];
          if (classes[i] != kActive) rgb = Vec3(vis.lit[i]);
          finite = is_finite(rgb);
        }
        if (!finite) {
          for (size_t seen = first_bad; i < seen && !first_bad.compare_exchange_weak(seen, i);) {
          }
          return;
        }
      }
    });
    if (const size_t i = first_bad; i != kNone)
      throw Error("method '" + info.name + "' produced a non-finite " +
                  (std::isfinite(vis.lit[i]) ? "colour" : "value") + " at pixel " +
                  std::to_string(i));
    result.per_light.push_back(std::move(vis));
  }
  return result;
}

}  // namespace penumbra
