// `penumbra view --script FILE`: the commands a script may give, parsed and checked before the
// window opens, so that a typo fails at once with the line it is on.
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "penumbra/scene/light.hpp"

namespace penumbra::viewer {

enum class ScriptOp {
  method,           // method NAME
  set,              // set KEY=VALUE (an option of the current method, or method.key=value)
  light_center,     // light_center X Y Z (world units)
  light_scale,      // light_scale S (size relative to the scene's light)
  light_shape,      // light_shape point|rect|disk|sphere
  light_radiance,   // light_radiance S (radiance relative to the scene's light)
  camera_orbit,     // camera_orbit DAZIMUTH_DEG DELEVATION_DEG
  view,             // view beauty|visibility|error|signed_error|split A B
  wait,             // until the current state's full-resolution frame is shown
  sleep,            // sleep MS (paces a scripted drag)
  screenshot,       // screenshot PATH.png
  save_visibility,  // save_visibility PATH.exr
  save_scene,       // save_scene PATH.json
  save_error,       // save_error PATH.json (the error views' numbers against the reference)
  light,            // light N (the light the light_* commands edit, from 0)
  time,             // time T (an animated scene: the time shown, seconds)
  play,             // play (an animated scene: the time follows the wall clock)
  pause,            // pause
  quit,
};

struct ScriptCommand {
  ScriptOp op = ScriptOp::quit;
  std::vector<std::string> words;  // the arguments, as written
  std::vector<double> numbers;     // the numeric arguments, parsed
  int line = 0;                    // 1-based line of the file
};

/// Reads and checks a script: one command per line, blank lines and `#` comments skipped. Throws
/// Error "FILE:LINE: ..." for an unknown command or a wrong argument.
std::vector<ScriptCommand> read_script(const std::filesystem::path& path);

/// A light shape by its name in the scene format.
std::optional<LightShape> parse_light_shape(const std::string& name);

/// "FILE:LINE: " for a command's messages at run time.
std::string script_location(const std::filesystem::path& path, const ScriptCommand& command);

}  // namespace penumbra::viewer
