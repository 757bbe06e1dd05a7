// The script's commands, run by the UI loop between frames: each returns false to be asked again
// on the next frame (a `wait` for the final frame, a `sleep`), true when it is done.
#include <cmath>
#include <cstdio>
#include <thread>

#include "penumbra/core/error.hpp"
#include "viewer.hpp"

namespace penumbra::viewer {

void Viewer::step_script() {
  if (args_.script.empty()) return;
  while (script_next_ < script_.size() && !quit_) {
    const ScriptCommand& c = script_[script_next_];
    try {
      if (!run_command(c)) return;
    } catch (const Error& e) {
      throw Error(script_location(args_.script, c) + e.what());
    }
    ++script_next_;
    script_waiting_ = false;
    // A screenshot is taken of the frame drawn next: nothing may change before it.
    if (c.op == ScriptOp::screenshot) return;
  }
  quit_ = true;  // a script ends the viewer when it ends
}

bool Viewer::run_command(const ScriptCommand& c) {
  const auto at_final_frame = [&] {
    script_waiting_ = true;
    if (job_error_generation_ == state_.generation && !job_error_.empty())
      throw Error("the frame failed: " + job_error_);
    return frame_is_final();
  };
  LightEdit& light = state_.lights[static_cast<size_t>(light_)];
  switch (c.op) {
    case ScriptOp::method:
      methods_->get(c.words[0]);  // unknown, or no GPU path → Error listing the names
      choose_method(c.words[0]);
      return true;
    case ScriptOp::set: {
      std::string key = c.words[0].substr(0, c.words[0].find('='));
      const std::string value = c.words[0].substr(c.words[0].find('=') + 1);
      std::string method = state_.method;
      if (const size_t dot = key.find('.'); dot != std::string::npos) {
        method = key.substr(0, dot);
        key = key.substr(dot + 1);
      }
      std::map<std::string, std::string> values = state_.options[method];
      values[key] = value;
      resolve_options(MethodRegistry::builtin().get(method), values);  // Error like --set's
      state_.options[method] = values;
      edited();
      return true;
    }
    case ScriptOp::light_center:
      light.center = Vec3(static_cast<float>(c.numbers[0]), static_cast<float>(c.numbers[1]),
                          static_cast<float>(c.numbers[2]));
      edited();
      return true;
    case ScriptOp::light_scale:
      light.scale = static_cast<float>(c.numbers[0]);
      edited();
      return true;
    case ScriptOp::light_shape:
      light.shape = *parse_light_shape(c.words[0]);
      edited();
      return true;
    case ScriptOp::light_radiance:
      light.intensity = static_cast<float>(c.numbers[0]);
      edited();
      return true;
    case ScriptOp::camera_orbit:
      state_.camera.orbit(static_cast<float>(c.numbers[0]), static_cast<float>(c.numbers[1]));
      edited();
      return true;
    case ScriptOp::view: {
      const ViewMode mode = *parse_view_mode(c.words[0]);
      if (mode == ViewMode::split) {
        for (int i = 0; i < 2; ++i) methods_->get(c.words[1 + i]);
        split_[0] = c.words[1];
        split_[1] = c.words[2];
      }
      const bool job_changes = mode == ViewMode::split || mode_ == ViewMode::split;
      mode_ = mode;
      picture_dirty_ = true;
      if (job_changes) edited();
      return true;
    }
    case ScriptOp::wait:
      return at_final_frame();
    case ScriptOp::sleep: {
      if (sleep_until_ == Clock::time_point{})
        sleep_until_ =
            Clock::now() + std::chrono::microseconds(static_cast<long long>(c.numbers[0] * 1000.0));
      if (Clock::now() < sleep_until_) return false;
      sleep_until_ = {};
      return true;
    }
    case ScriptOp::screenshot:
      screenshot_ = c.words[0];
      return true;
    case ScriptOp::save_visibility:
      if (!at_final_frame()) return false;
      save_visibility(c.words[0]);
      return true;
    case ScriptOp::save_scene:
      if (!at_final_frame()) return false;
      save_scene(c.words[0]);
      return true;
    case ScriptOp::save_error:
      if (!at_final_frame()) return false;
      save_error(c.words[0]);
      return true;
    case ScriptOp::light: {
      const double n = c.numbers[0];
      if (n != std::floor(n) || n < 0 || n >= static_cast<double>(state_.lights.size()))
        throw Error("light: the scene's lights are 0 to " +
                    std::to_string(state_.lights.size() - 1) + ", not " + c.words[0]);
      light_ = static_cast<int>(n);
      picture_dirty_ = true;  // the visibility and error views show the light edited
      return true;
    }
    case ScriptOp::time: {
      const Animation& a = base_->animation;
      const double t = c.numbers[0];
      if (a.empty()) throw Error("time: the scene has no animation");
      if (t < a.start_s || t > a.end_s) {
        char range[64];
        std::snprintf(range, sizeof range, "%g to %g s", a.start_s, a.end_s);
        throw Error("time: the animation runs from " + std::string(range) + ", not " + c.words[0]);
      }
      state_.time_s = t;
      state_.playing = false;
      edited();
      return true;
    }
    case ScriptOp::play:
    case ScriptOp::pause:
      if (base_->animation.empty())
        throw Error(std::string(c.op == ScriptOp::play ? "play" : "pause") +
                    ": the scene has no animation");
      state_.playing = c.op == ScriptOp::play;
      if (!state_.playing) edited();  // settle to the full-resolution frame of this time
      return true;
    case ScriptOp::quit:
      quit_ = true;
      return true;
  }
  return true;
}

}  // namespace penumbra::viewer
