#include "render_worker.hpp"

#include <tbb/task_arena.h>

#include <exception>

#include "penumbra/core/error.hpp"
#include "penumbra/core/stats.hpp"
#include "penumbra/pipeline/shading.hpp"

namespace penumbra::viewer {

std::shared_ptr<const EmbreeScene> SharedBvh::of(const Scene& scene) {
  std::call_once(once, [&] { bvh = std::make_shared<const EmbreeScene>(scene); });
  return bvh;
}

RenderWorker::RenderWorker(std::function<void()> notify, bool low_priority)
    : notify_(std::move(notify)), low_priority_(low_priority), thread_([this] { loop(); }) {}

RenderWorker::~RenderWorker() {
  {
    const std::lock_guard lock(mutex_);
    stop_ = true;
    pending_.reset();
  }
  wake_.notify_all();
  thread_.join();  // after the job it is running: methods cannot be interrupted
}

void RenderWorker::submit(RenderJob job) {
  {
    const std::lock_guard lock(mutex_);
    pending_ = std::make_unique<RenderJob>(std::move(job));
  }
  wake_.notify_all();
}

std::shared_ptr<RenderOutput> RenderWorker::take() {
  const std::lock_guard lock(mutex_);
  return std::move(done_);
}

bool RenderWorker::busy() const {
  const std::lock_guard lock(mutex_);
  return running_ || pending_ != nullptr;
}

void RenderWorker::loop() {
  tbb::task_arena arena(
      tbb::task_arena::automatic, 1,
      low_priority_ ? tbb::task_arena::priority::low : tbb::task_arena::priority::normal);
  for (;;) {
    std::unique_ptr<RenderJob> job;
    {
      std::unique_lock lock(mutex_);
      wake_.wait(lock, [&] { return stop_ || pending_ != nullptr; });
      if (stop_) return;
      job = std::move(pending_);
      running_ = true;
    }
    std::shared_ptr<RenderOutput> out;
    arena.execute([&] { out = run(*job); });
    {
      const std::lock_guard lock(mutex_);
      done_ = std::move(out);
      running_ = false;
    }
    if (notify_) notify_();
  }
}

ShadowMethod& RenderWorker::prepared(const RenderJob& job, size_t m) const {
  if (prepared_for_ != job.base) {
    prepared_.clear();
    prepared_for_ = job.base;
  }
  std::string key = job.methods[m]->name;
  for (const auto& [option, value] : job.options[m].values()) key += "/" + option + "=" + value;
  std::unique_ptr<ShadowMethod>& method = prepared_[key];
  if (!method) {
    std::unique_ptr<ShadowMethod> made = job.methods[m]->create(job.options[m]);
    made->prepare(*job.base);
    method = std::move(made);
  }
  return *method;
}

std::shared_ptr<RenderOutput> RenderWorker::run(const RenderJob& job) const {
  auto out = std::make_shared<RenderOutput>();
  out->job = job;
  try {
    const auto scene_start = std::chrono::steady_clock::now();
    out->scene = std::make_shared<const Scene>(
        edited_scene(*job.base, job.lights, job.camera, job.time_s, job.camera_moved));
    out->scene_ms = elapsed_ms(scene_start);
    const auto start = std::chrono::steady_clock::now();
    // Moving meshes: this pose's own BVH, and the methods prepared on it (inside their times).
    const bool moving = job.base->animation.moves_geometry();
    out->frame = moving ? std::make_unique<Frame>(*out->scene, job.samples)
                        : std::make_unique<Frame>(*out->scene, job.samples, job.bvh->of(*job.base));
    out->frame_ms = elapsed_ms(start);
    for (size_t m = 0; m < job.methods.size(); ++m)
      out->results.push_back(
          moving ? out->frame->run(*job.methods[m], job.options[m], false)
                 : out->frame->run(*job.methods[m], prepared(job, m), job.options[m], false));
    const auto shade_start = std::chrono::steady_clock::now();
    if (job.shade)
      for (const MethodResult& result : out->results) {
        std::vector<const Visibility*> per_light;
        for (const Visibility& v : result.per_light) per_light.push_back(&v);
        out->beauty.push_back(
            report::srgb_picture(shade(*out->frame, per_light, ShadingMode::modulate)));
      }
    out->shade_ms = elapsed_ms(shade_start);
  } catch (const std::bad_alloc&) {
    out->error = "out of memory (try a smaller --size or fewer --samples)";
  } catch (const std::exception& e) {
    out->error = e.what();
  }
  out->finished = std::chrono::steady_clock::now();
  return out;
}

}  // namespace penumbra::viewer
