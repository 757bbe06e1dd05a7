// `penumbra view`: the window, its state and its workers. The UI thread only edits the state,
// submits jobs and shows what the workers made (viewer.cpp); the panel (panel.cpp), the mouse
// (controls.cpp), the pictures of each view (pictures.cpp) and the script (run_script.cpp) are
// its parts.
#pragma once

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "gl_window.hpp"
#include "pictures.hpp"
#include "render_worker.hpp"
#include "script.hpp"
#include "view_state.hpp"
#include "viewer_methods.hpp"

namespace penumbra::viewer {

struct ViewerArgs {
  std::string scene;
  std::string method;  // empty: `exact`, or the first GPU method with --backend vulkan
  std::string size;
  int samples = 4;
  std::string pattern = "grid";
  uint64_t seed = 1;
  std::map<std::string, std::map<std::string, std::string>> options;  // method → key → text
  std::string script;                                                 // its path, for messages
  int preview_divisor = 4;
  double settle_ms = 200.0;
  bool trace = false;  // one line on stderr per frame shown: where its time went
  // What the error views compare against: "exact", or "raytrace" with reference_samples² samples
  // (for scenes where exact is too slow).
  std::string reference = "exact";
  int reference_samples = 32;
  std::string backend = "cpu";  // or "vulkan": the methods (not the reference) on the GPU
  std::string vk_device;        // as `render --vk-device`
};

/// The reference's name as the panel and the files show it: `exact` or `raytrace 32×32`.
std::string reference_label(const ViewerArgs& args);

/// Opens the window and runs until it is closed (or the script, already read and checked, ends).
/// Throws Error.
void run_viewer(const ViewerArgs& args, Scene scene, std::vector<ScriptCommand> script);

using Clock = std::chrono::steady_clock;

/// Latencies the script mode prints at its end: from each edit to the first frame showing it.
struct LatencyLog {
  struct Edit {
    uint64_t generation;
    Clock::time_point at;
    double first_frame_ms = -1.0;  // < 0: not shown yet
    bool preview = false;          // the first frame showing it was a preview
  };
  std::vector<Edit> edits;
  double longest_ui_frame_ms = 0.0, ui_frames_ms = 0.0;
  long ui_frames = 0;
  void ui_frame(double ms) {
    longest_ui_frame_ms = std::max(longest_ui_frame_ms, ms);
    ui_frames_ms += ms;
    ++ui_frames;
  }
  void edited(uint64_t generation) { edits.push_back({generation, Clock::now()}); }
  void shown(uint64_t generation, bool preview);
  std::string summary() const;
};

class Viewer {
 public:
  Viewer(const ViewerArgs& args, Scene scene, std::vector<ScriptCommand> script,
         std::shared_ptr<const ViewerMethods> methods);
  ~Viewer();
  void run();

 private:
  // viewer.cpp: jobs and results.
  void schedule();
  RenderJob make_job(bool preview, bool reference) const;
  void collect();
  void accept(std::shared_ptr<RenderOutput> out, bool reference);
  void trace(const RenderOutput& out, bool reference) const;
  bool frame_is_final() const;
  /// The method shown is the reference itself (`exact`, with an exact reference): no second run.
  bool method_is_reference() const;
  void edited();
  /// A playing animation: its time advanced by the wall time since the last call, looping.
  void advance_playback(Clock::time_point now);
  void refresh_picture();
  // panel.cpp
  void draw_panel();
  void draw_image();
  void method_panel();
  void option_widgets();
  void light_panel();
  void view_panel();
  void animation_panel();
  void stats_panel();
  void files_panel();
  bool set_option(const std::string& key, const std::string& text, std::string* error);
  void choose_method(const std::string& name);
  // controls.cpp: the mouse on the image.
  void handle_mouse();
  // run_script.cpp
  void step_script();
  bool run_command(const ScriptCommand& c);
  // Files: what the panel's buttons and the script write.
  void save_visibility(const std::filesystem::path& path) const;
  void save_scene(const std::filesystem::path& path) const;
  void save_error(const std::filesystem::path& path) const;

  ViewerArgs args_;
  std::shared_ptr<const ViewerMethods> methods_;
  std::shared_ptr<const Scene> base_;  // as loaded; every job edits a copy
  std::shared_ptr<SharedBvh> bvh_ = std::make_shared<SharedBvh>();
  float scene_diagonal_ = 1.0f;
  ViewState state_;
  ViewMode mode_ = ViewMode::beauty;
  std::string split_[2];
  int light_ = 0;  // the light edited and shown in the visibility and error views
  GlWindow window_;
  RenderWorker preview_worker_, full_worker_, reference_worker_;
  std::shared_ptr<RenderOutput> shown_, reference_;
  std::string job_error_;  // the last failed job's message (shown in the panel)
  uint64_t preview_sent_ = 0, full_sent_ = 0, reference_sent_ = 0;  // generations submitted
  bool reference_preview_sent_ = false;
  Clock::time_point last_edit_;
  bool picture_dirty_ = true;
  PictureInfo picture_info_;
  ImageRect image_rect_;      // where the image is drawn in the window
  int drag_button_ = -1;      // the mouse button whose drag began on the image
  bool drag_light_ = false;   // that drag moves the light
  std::string option_error_;  // why the last option edit was refused
  std::string status_;        // the last file written by a panel button, or why not
  uint64_t job_error_generation_ = 0;
  // The script.
  std::vector<ScriptCommand> script_;
  size_t script_next_ = 0;
  bool script_waiting_ = false;  // at a `wait`: the state counts as still
  Clock::time_point sleep_until_;
  Clock::time_point played_at_;  // when advance_playback last moved the time
  std::optional<std::filesystem::path> screenshot_;
  LatencyLog latency_;
  bool quit_ = false;
  long ui_frames_ = 0;
  char file_stem_[256] = "penumbra_view";
};

}  // namespace penumbra::viewer
