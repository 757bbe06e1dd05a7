#include "viewer.hpp"

#include <imgui.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <thread>

#include "penumbra/core/error.hpp"
#include "penumbra/core/files.hpp"
#include "penumbra/io/image_io.hpp"
#include "penumbra/pipeline/outputs.hpp"
#include "penumbra/report/report.hpp"
#include "penumbra/scene/scene_writer.hpp"

namespace penumbra::viewer {

namespace {

constexpr int kPanelWidth = 380;
constexpr int kMinWindowHeight = 720;

/// Small images are shown enlarged: at least 512 pixels on their longer side.
int initial_scale(int width, int height) {
  return std::max(1, 512 / std::max(width, height));
}

double ms_between(Clock::time_point a, Clock::time_point b) {
  return std::chrono::duration<double, std::milli>(b - a).count();
}

}  // namespace

void LatencyLog::shown(uint64_t generation, bool preview) {
  const auto now = Clock::now();
  for (Edit& e : edits)
    if (e.generation <= generation && e.first_frame_ms < 0.0) {
      e.first_frame_ms = ms_between(e.at, now);
      e.preview = preview;
    }
}

std::string LatencyLog::summary() const {
  std::vector<double> ms;
  int previews = 0;
  for (const Edit& e : edits)
    if (e.first_frame_ms >= 0.0) {
      ms.push_back(e.first_frame_ms);
      previews += e.preview ? 1 : 0;
    }
  char line[256];
  if (ms.empty()) {
    std::snprintf(line, sizeof line, "view: no edits; %ld UI frames, mean %.1f ms, longest %.1f ms",
                  ui_frames, ui_frames_ms / std::max(ui_frames, 1L), longest_ui_frame_ms);
    return line;
  }
  std::sort(ms.begin(), ms.end());
  std::snprintf(line, sizeof line,
                "view: %zu edits, first frame showing each: median %.1f ms, p90 %.1f ms, max "
                "%.1f ms (%d of them previews); %ld UI frames, mean %.1f ms, longest %.1f ms",
                ms.size(), ms[ms.size() / 2], ms[ms.size() * 9 / 10], ms.back(), previews,
                ui_frames, ui_frames_ms / std::max(ui_frames, 1L), longest_ui_frame_ms);
  return line;
}

Viewer::Viewer(const ViewerArgs& args, Scene scene, std::vector<ScriptCommand> script,
               std::shared_ptr<const ViewerMethods> methods)
    : args_(args),
      methods_(std::move(methods)),
      base_(std::make_shared<const Scene>(std::move(scene))),
      state_(*base_, args.method, LightSampleSpec{}),
      window_(
          base_->camera.width * initial_scale(base_->camera.width, base_->camera.height) +
              kPanelWidth,
          std::max(kMinWindowHeight,
                   base_->camera.height * initial_scale(base_->camera.width, base_->camera.height)),
          "penumbra view: " + base_->name),
      preview_worker_(GlWindow::wake, false),
      full_worker_(GlWindow::wake, true),
      reference_worker_(GlWindow::wake, true),
      script_(std::move(script)) {
  // A script's run ignores the pointer (wherever the display put it: no tooltip, no drag).
  if (!args.script.empty()) ImGui::GetIO().ConfigFlags |= ImGuiConfigFlags_NoMouse;
  state_.options = args.options;
  const Bounds3 bounds = base_->bounds();
  scene_diagonal_ = glm::length(bounds.hi - bounds.lo);
  state_.samples.k = args.samples;
  state_.samples.seed = args.seed;
  state_.samples.pattern = *parse_sample_pattern(args.pattern);
  split_[0] = methods_->gpu() ? methods_->listed().front()->name : "exact";
  split_[1] = args.method;
  last_edit_ = Clock::now() - std::chrono::hours(1);
}

Viewer::~Viewer() = default;

void Viewer::edited() {
  state_.changed();
  last_edit_ = Clock::now();
  latency_.edited(state_.generation);
}

void Viewer::advance_playback(Clock::time_point now) {
  const Animation& a = base_->animation;
  if (!state_.playing || a.empty()) {
    played_at_ = now;
    return;
  }
  const double span = a.end_s - a.start_s;
  double t = state_.time_s + ms_between(played_at_, now) / 1000.0;
  if (t > a.end_s) t = span > 0.0 ? a.start_s + std::fmod(t - a.start_s, span) : a.start_s;
  played_at_ = now;
  state_.time_s = t;
  edited();  // the frames shown while it plays are previews; a pause settles to full resolution
}

std::string reference_label(const ViewerArgs& args) {
  return report::reference_label(args.reference, args.reference_samples);
}

bool Viewer::method_is_reference() const {
  return args_.reference == "exact" && state_.method == "exact";
}

RenderJob Viewer::make_job(bool preview, bool reference) const {
  const MethodRegistry& registry = MethodRegistry::builtin();
  RenderJob job;
  job.generation = state_.generation;
  job.preview = preview;
  int w = state_.width, h = state_.height;
  if (preview) {
    const int d = args_.preview_divisor;
    w = std::max(1, (w + d - 1) / d);
    h = std::max(1, (h + d - 1) / d);
  }
  job.base = base_;
  job.bvh = bvh_;
  job.lights = state_.lights;
  job.camera = state_.camera.camera();
  job.camera.width = w;
  job.camera.height = h;
  job.time_s = state_.time_s;
  job.camera_moved = state_.camera.moved();
  job.samples = state_.samples;
  std::vector<std::string> names{state_.method};
  if (reference) {
    names = {args_.reference};
    if (args_.reference == "raytrace") job.samples.k = args_.reference_samples;
    job.shade = false;
  } else if (mode_ == ViewMode::split) {
    names = {split_[0], split_[1]};
  }
  for (const std::string& name : names) {
    const MethodInfo& info = reference ? registry.get(name) : methods_->get(name);
    const auto it = state_.options.find(name);
    job.methods.push_back(&info);
    job.options.push_back(resolve_options(
        info, it == state_.options.end() ? std::map<std::string, std::string>{} : it->second));
  }
  job.submitted = Clock::now();
  return job;
}

void Viewer::schedule() {
  const uint64_t g = state_.generation;
  const bool still = script_waiting_ || args_.preview_divisor <= 1 ||
                     ms_between(last_edit_, Clock::now()) >= args_.settle_ms;
  const bool reference = needs_reference(mode_) && !method_is_reference();
  const uint64_t reference_key = 2 * g + (still ? 0 : 1);
  try {
    if (!still && preview_sent_ != g) {
      preview_worker_.submit(make_job(true, false));
      preview_sent_ = g;
    }
    if (still && full_sent_ != g) {
      full_worker_.submit(make_job(false, false));
      full_sent_ = g;
    }
    if (reference && reference_sent_ != reference_key) {
      reference_worker_.submit(make_job(!still, true));
      reference_sent_ = reference_key;
    }
  } catch (const Error& e) {  // an edit the scene cannot take (e.g. a light out of range)
    job_error_ = e.what();
    job_error_generation_ = g;
    preview_sent_ = full_sent_ = g;
    reference_sent_ = reference_key;
  }
}

void Viewer::accept(std::shared_ptr<RenderOutput> out, bool reference) {
  const RenderJob& job = out->job;
  if (!out->error.empty()) {
    if (job.generation == state_.generation) {
      job_error_ = out->error;
      job_error_generation_ = job.generation;
    }
    return;
  }
  std::shared_ptr<RenderOutput>& slot = reference ? reference_ : shown_;
  // Stale: older than what is shown, or a preview of what is shown in full.
  if (slot && (job.generation < slot->job.generation ||
               (job.generation == slot->job.generation && job.preview && !slot->job.preview)))
    return;
  if (!reference) latency_.shown(job.generation, job.preview);
  if (args_.trace) trace(*out, reference);
  slot = std::move(out);
  picture_dirty_ = true;
}

void Viewer::trace(const RenderOutput& out, bool reference) const {
  double method_ms = 0.0;
  for (const MethodResult& r : out.results) method_ms += r.total_ms;
  std::fprintf(stderr,
               "view: %s generation %llu, %s %dx%d: scene %.1f + frame %.1f + %s %.1f + shading "
               "%.1f ms; shown %.1f ms after its job was submitted\n",
               reference ? "reference" : "frame",
               static_cast<unsigned long long>(out.job.generation),
               out.job.preview ? "preview" : "full", out.job.camera.width, out.job.camera.height,
               out.scene_ms, out.frame_ms, out.results.front().method.c_str(), method_ms,
               out.shade_ms, ms_between(out.job.submitted, Clock::now()));
}

void Viewer::collect() {
  if (auto out = preview_worker_.take()) accept(std::move(out), false);
  if (auto out = full_worker_.take()) accept(std::move(out), false);
  if (auto out = reference_worker_.take()) accept(std::move(out), true);
}

void Viewer::refresh_picture() {
  if (!picture_dirty_ || !shown_) return;
  const bool self_reference = args_.reference == "exact" && shown_->results.size() == 1 &&
                              shown_->results.front().method == "exact";
  const RenderOutput* reference = self_reference ? shown_.get() : reference_.get();
  window_.set_image(make_picture(mode_, light_, *shown_, reference, picture_info_));
  picture_dirty_ = false;
}

bool Viewer::frame_is_final() const {
  const uint64_t g = state_.generation;
  if (!shown_ || shown_->job.generation != g || shown_->job.preview || picture_dirty_) return false;
  if (needs_reference(mode_) && !method_is_reference())
    return reference_ && reference_->job.generation == g && !reference_->job.preview;
  return true;
}

void Viewer::save_visibility(const std::filesystem::path& path) const {
  const VisibilityLayers layers = visibility_layers(*shown_->frame, shown_->results.front());
  write_exr_views(path, layers.layers);
}

void Viewer::save_scene(const std::filesystem::path& path) const {
  write_scene_file(*shown_->scene, path);
}

void Viewer::save_error(const std::filesystem::path& path) const {
  if (!picture_info_.error) throw Error("save_error: no error to save (in the error views only)");
  nlohmann::json j = to_json(*picture_info_.error);
  j["method"] = state_.method;
  j["reference"] = reference_label(args_);
  write_text_file(path, j.dump(2) + "\n");
}

void Viewer::run() {
  auto frame_start = Clock::now();
  while (!quit_ && !window_.should_close()) {
    // The window sleeps until an event, a worker's result (it wakes the loop), the end of the
    // settle time after an edit, or a script's next command: no frame is drawn for nothing
    // (under a software OpenGL every frame costs the workers CPU time).
    const auto now = Clock::now();
    double timeout_s = 0.5;
    if (!args_.script.empty()) {
      if (sleep_until_ != Clock::time_point{})
        timeout_s = ms_between(now, sleep_until_) / 1000.0;
      else if (!script_waiting_ || frame_is_final())
        timeout_s = 0.0;
    } else if (const double since_edit = ms_between(last_edit_, now);
               since_edit < args_.settle_ms) {
      timeout_s = (args_.settle_ms - since_edit) / 1000.0;
    }
    if (state_.playing) timeout_s = std::min(timeout_s, 1.0 / 60.0);
    window_.wait_events(std::max(timeout_s, 0.0));
    frame_start = Clock::now();
    collect();
    step_script();
    if (quit_) break;
    advance_playback(frame_start);
    schedule();
    refresh_picture();
    window_.begin_frame();
    draw_image();  // first: the gizmo and the panel are drawn over it
    handle_mouse();
    draw_panel();
    try {
      window_.end_frame(screenshot_ ? &*screenshot_ : nullptr);
    } catch (const Error& e) {    // the screenshot could not be written
      if (!args_.script.empty())  // the command that asked for it is the last one run
        throw Error(script_location(args_.script, script_[script_next_ - 1]) + e.what());
      status_ = e.what();
    }
    screenshot_.reset();
    // The first frames build ImGui's font atlas and compile its shaders: not a stall.
    if (++ui_frames_ > 2) latency_.ui_frame(ms_between(frame_start, Clock::now()));
  }
  if (!args_.script.empty()) std::fprintf(stderr, "%s\n", latency_.summary().c_str());
}

void run_viewer(const ViewerArgs& in, Scene scene, std::vector<ScriptCommand> script) {
  ViewerArgs args = in;
  // The device and the method are checked before the window opens.
  auto methods = std::make_shared<const ViewerMethods>(args.backend, args.vk_device);
  if (args.method.empty()) args.method = methods->gpu() ? methods->listed().front()->name : "exact";
  methods->get(args.method);
  if (methods->gpu()) std::fprintf(stderr, "vulkan device: %s\n", methods->device_name().c_str());
  Viewer viewer(args, std::move(scene), std::move(script), std::move(methods));
  viewer.run();
}

}  // namespace penumbra::viewer
