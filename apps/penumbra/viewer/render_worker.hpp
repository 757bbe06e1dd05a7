// The viewer's computations, off the UI thread: one worker thread runs the newest job it was
// given (a job submitted while another runs replaces any job still waiting: stale requests are
// dropped, never queued), and hands back what it made; the UI polls for it and never waits.
#pragma once

#include <chrono>
#include <condition_variable>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "penumbra/pipeline/frame.hpp"
#include "penumbra/report/report_images.hpp"
#include "view_state.hpp"

namespace penumbra::viewer {

/// The scene's BVH, built by whichever worker needs it first and shared by every frame after: the
/// viewer's edits change lights and camera, never the meshes (a scene whose animation moves its
/// meshes gets a BVH per frame instead).
struct SharedBvh {
  std::once_flag once;
  std::shared_ptr<const EmbreeScene> bvh;
  /// The BVH of `scene` (built on the first call; a failed build is tried again next time).
  std::shared_ptr<const EmbreeScene> of(const Scene& scene);
};

struct RenderJob {
  uint64_t generation = 0;  // the ViewState generation it renders
  bool preview = false;     // a reduced resolution, while the user drags
  // The scene is edited on the worker (a copy of every mesh: not on the UI thread).
  std::shared_ptr<const Scene> base;
  std::shared_ptr<SharedBvh> bvh;  // of `base`
  std::vector<LightEdit> lights;
  Camera camera;              // at the job's resolution
  double time_s = 0.0;        // an animated scene's time (edited_scene)
  bool camera_moved = false;  // the user's camera rather than an animated one
  LightSampleSpec samples;
  std::vector<const MethodInfo*> methods;  // one, or two for the split view
  std::vector<MethodOptions> options;
  bool shade = true;  // make the beauty pictures
  std::chrono::steady_clock::time_point submitted;
};

/// What a job made. Members are destroyed in reverse order: the frame before the scene it
/// points to.
struct RenderOutput {
  RenderJob job;
  std::shared_ptr<const Scene> scene;  // the edited scene the frame renders
  std::unique_ptr<Frame> frame;
  std::vector<MethodResult> results;      // one per job method
  std::vector<report::Rgb8Image> beauty;  // sRGB, one per job method (when job.shade)
  double scene_ms = 0.0;                  // the edited scene: copied and validated
  double frame_ms = 0.0;                  // G-buffer, receiver classes (and the first job's BVH)
  double shade_ms = 0.0;                  // unshadowed irradiance and beauty pictures
  std::string error;                      // a failed job: its one-line message, nothing else set
  std::chrono::steady_clock::time_point finished;
};

class RenderWorker {
 public:
  /// `notify` is called on the worker thread after each job (to wake the UI's event loop).
  /// `low_priority`: the job's parallel work runs in a low-priority oneTBB arena, so that it
  /// yields the cores to a normal-priority worker (the reference behind the method).
  RenderWorker(std::function<void()> notify, bool low_priority);
  ~RenderWorker();
  RenderWorker(const RenderWorker&) = delete;
  RenderWorker& operator=(const RenderWorker&) = delete;

  void submit(RenderJob job);
  /// The newest finished output not yet taken (older finished ones are dropped), or null.
  std::shared_ptr<RenderOutput> take();
  /// A job is waiting or running.
  bool busy() const;

 private:
  void loop();
  std::shared_ptr<RenderOutput> run(const RenderJob& job) const;

  /// The job's methods, created and prepared (ShadowMethod::prepare) on `prepared_for_`, the base
  /// scene whose meshes every edit keeps: a moved light or camera reuses them. Worker thread only.
  ShadowMethod& prepared(const RenderJob& job, size_t m) const;

  mutable std::shared_ptr<const Scene> prepared_for_;
  mutable std::map<std::string, std::unique_ptr<ShadowMethod>> prepared_;  // by name and options
  std::function<void()> notify_;
  bool low_priority_;
  mutable std::mutex mutex_;
  std::condition_variable wake_;
  std::unique_ptr<RenderJob> pending_;
  std::shared_ptr<RenderOutput> done_;
  bool running_ = false;
  bool stop_ = false;
  std::thread thread_;
};

}  // namespace penumbra::viewer
