#include "script.hpp"

#include <charconv>
#include <cmath>
#include <fstream>
#include <map>
#include <sstream>

#include "penumbra/core/error.hpp"
#include "penumbra/core/suggest.hpp"

namespace penumbra::viewer {

namespace {

struct Syntax {
  ScriptOp op;
  int min_words, max_words;
  int numbers;  // leading arguments that must be finite numbers
  const char* usage;
};

const std::map<std::string, Syntax>& syntax() {
  static const std::map<std::string, Syntax> table = {
      {"method", {ScriptOp::method, 1, 1, 0, "method NAME"}},
      {"set", {ScriptOp::set, 1, 1, 0, "set KEY=VALUE"}},
      {"light_center", {ScriptOp::light_center, 3, 3, 3, "light_center X Y Z"}},
      {"light_scale", {ScriptOp::light_scale, 1, 1, 1, "light_scale S"}},
      {"light_shape", {ScriptOp::light_shape, 1, 1, 0, "light_shape point|rect|disk|sphere"}},
      {"light_radiance", {ScriptOp::light_radiance, 1, 1, 1, "light_radiance S"}},
      {"camera_orbit",
       {ScriptOp::camera_orbit, 2, 2, 2, "camera_orbit DAZIMUTH_DEG DELEVATION_DEG"}},
      {"view", {ScriptOp::view, 1, 3, 0, "view beauty|visibility|error|signed_error|split A B"}},
      {"wait", {ScriptOp::wait, 0, 0, 0, "wait"}},
      {"sleep", {ScriptOp::sleep, 1, 1, 1, "sleep MS"}},
      {"screenshot", {ScriptOp::screenshot, 1, 1, 0, "screenshot PATH.png"}},
      {"save_visibility", {ScriptOp::save_visibility, 1, 1, 0, "save_visibility PATH.exr"}},
      {"save_scene", {ScriptOp::save_scene, 1, 1, 0, "save_scene PATH.json"}},
      {"save_error", {ScriptOp::save_error, 1, 1, 0, "save_error PATH.json"}},
      {"light", {ScriptOp::light, 1, 1, 1, "light N"}},
      {"time", {ScriptOp::time, 1, 1, 1, "time SECONDS"}},
      {"play", {ScriptOp::play, 0, 0, 0, "play"}},
      {"pause", {ScriptOp::pause, 0, 0, 0, "pause"}},
      {"quit", {ScriptOp::quit, 0, 0, 0, "quit"}},
  };
  return table;
}

double parse_number(const std::string& word, const std::string& where) {
  double value = 0.0;
  const auto [end, ec] = std::from_chars(word.data(), word.data() + word.size(), value);
  if (ec != std::errc{} || end != word.data() + word.size() || !std::isfinite(value))
    throw Error(where + "expected a finite number, got " + quote(word));
  return value;
}

void check_view(const ScriptCommand& c, const std::string& where) {
  const std::string& mode = c.words[0];
  if (mode == "split") {
    if (c.words.size() != 3) throw Error(where + "expected: view split METHOD_A METHOD_B");
    return;
  }
  if (c.words.size() != 1) throw Error(where + "expected: view " + mode);
  if (mode != "beauty" && mode != "visibility" && mode != "error" && mode != "signed_error")
    throw Error(where + "unknown view " + quote(mode) +
                " (views: beauty, visibility, error, signed_error, split A B)");
}

ScriptCommand parse_line(const std::string& text, int line, const std::string& where) {
  std::istringstream in(text);
  std::string name;
  in >> name;
  const auto it = syntax().find(name);
  if (it == syntax().end()) {
    std::vector<std::string> names;
    for (const auto& [n, s] : syntax()) names.push_back(n);
    throw Error(where + "unknown command " + quote(name) + did_you_mean(name, names));
  }
  const Syntax& s = it->second;
  ScriptCommand c;
  c.op = s.op;
  c.line = line;
  for (std::string word; in >> word;) c.words.push_back(word);
  const int n = static_cast<int>(c.words.size());
  if (n < s.min_words || n > s.max_words) throw Error(where + "expected: " + s.usage);
  for (int i = 0; i < s.numbers; ++i) c.numbers.push_back(parse_number(c.words[i], where));
  if (c.op == ScriptOp::view) check_view(c, where);
  if (c.op == ScriptOp::set && c.words[0].find('=') == std::string::npos)
    throw Error(where + "expected: set KEY=VALUE, got " + quote(c.words[0]));
  if ((c.op == ScriptOp::light_scale || c.op == ScriptOp::light_radiance) && !(c.numbers[0] > 0.0))
    throw Error(where + c.words[0] + ": must be > 0");
  if (c.op == ScriptOp::light_shape && !parse_light_shape(c.words[0]))
    throw Error(where + "unknown light shape " + quote(c.words[0]) +
                " (point, rect, disk, sphere)");
  if (c.op == ScriptOp::sleep && (c.numbers[0] < 0.0 || c.numbers[0] > 600000.0))
    throw Error(where + "sleep takes 0 to 600000 milliseconds");
  return c;
}

}  // namespace

std::vector<ScriptCommand> read_script(const std::filesystem::path& path) {
  std::ifstream file(path);
  if (!file) throw Error("--script: cannot read " + quote(path.string(), 200));
  std::vector<ScriptCommand> out;
  std::string text;
  for (int line = 1; std::getline(file, text); ++line) {
    const size_t hash = text.find('#');
    if (hash != std::string::npos) text.resize(hash);
    if (text.find_first_not_of(" \t\r") == std::string::npos) continue;
    out.push_back(
        parse_line(text, line, quote(path.string(), 200) + ":" + std::to_string(line) + ": "));
  }
  return out;
}

std::optional<LightShape> parse_light_shape(const std::string& name) {
  for (LightShape s : {LightShape::point, LightShape::rect, LightShape::disk, LightShape::sphere})
    if (name == to_string(s)) return s;
  return std::nullopt;
}

std::string script_location(const std::filesystem::path& path, const ScriptCommand& command) {
  return quote(path.string(), 200) + ":" + std::to_string(command.line) + ": ";
}

}  // namespace penumbra::viewer
