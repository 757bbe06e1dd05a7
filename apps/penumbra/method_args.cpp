#include "method_args.hpp"

#include <algorithm>
#include <cstdio>

#include "penumbra/core/error.hpp"

namespace penumbra::cli {

void parse_size(const std::string& text, Camera& camera) {
  int w = 0, h = 0;
  char x = 0, extra = 0;
  if (std::sscanf(text.c_str(), "%d%c%d%c", &w, &x, &h, &extra) != 3 || (x != 'x' && x != 'X') ||
      w < 1 || h < 1 || w > 16384 || h > 16384)
    throw Error("--size: expected WxH with 1..16384 pixels each, got " + quote(text));
  camera.width = w;
  camera.height = h;
}

std::map<std::string, std::map<std::string, std::string>> parse_sets(
    const std::vector<std::string>& sets) {
  std::map<std::string, std::map<std::string, std::string>> out;
  for (const std::string& s : sets) {
    const size_t dot = s.find('.'), eq = s.find('=');
    if (dot == std::string::npos || eq == std::string::npos || dot > eq || dot == 0 ||
        eq == dot + 1)
      throw Error("--set: expected method.option=value, got " + quote(s));
    out[s.substr(0, dot)][s.substr(dot + 1, eq - dot - 1)] = s.substr(eq + 1);
  }
  return out;
}

std::vector<const MethodInfo*> selected_methods(const std::vector<std::string>& names) {
  const MethodRegistry& registry = MethodRegistry::builtin();
  std::vector<const MethodInfo*> out;
  for (const std::string& name : names) {
    if (name == "all") {
      for (const MethodInfo& m : registry.methods()) out.push_back(&m);
    } else {
      out.push_back(&registry.get(name));
    }
  }
  // `exact` first: every other method is measured against it.
  std::stable_sort(out.begin(), out.end(), [](const MethodInfo* a, const MethodInfo* b) {
    return a->name == "exact" && b->name != "exact";
  });
  std::vector<const MethodInfo*> unique;
  for (const MethodInfo* m : out)
    if (std::find(unique.begin(), unique.end(), m) == unique.end()) unique.push_back(m);
  return unique;
}

std::vector<MethodOptions> resolve_method_options(const std::vector<const MethodInfo*>& methods,
                                                  const std::vector<std::string>& set_args) {
  const auto sets = parse_sets(set_args);
  for (const auto& [name, values] : sets) {
    MethodRegistry::builtin().get(name);  // unknown method → error
    if (std::none_of(methods.begin(), methods.end(),
                     [&](const MethodInfo* m) { return m->name == name; }))
      std::fprintf(stderr, "penumbra: warning: --set for %s, which is not rendered\n",
                   quote(name).c_str());
  }
  std::vector<MethodOptions> options;
  for (const MethodInfo* m : methods) {
    const auto it = sets.find(m->name);
    options.push_back(
        resolve_options(*m, it == sets.end() ? std::map<std::string, std::string>{} : it->second));
  }
  return options;
}

SamplePattern parse_pattern(const std::string& name) {
  const auto pattern = parse_sample_pattern(name);
  if (!pattern) throw Error("--pattern: unknown light-sample pattern " + quote(name));
  return *pattern;
}

void add_framing_options(CLI::App& cmd, FramingArgs& args) {
  cmd.add_option("--light-size", args.light_size,
                 "Model file scenes: side of the square light, in model bounding-box diagonals")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  cmd.add_option("--light-height", args.light_height,
                 "Model file scenes: light height above the model's centre, in diagonals")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  cmd.add_option("--up", args.up,
                 "Model file scenes: the model's up axis, y, z or auto (the axis with more "
                 "triangle area at its bottom; y unless z has twice as much)")
      ->check(CLI::IsMember({"y", "z", "auto"}))
      ->capture_default_str();
}

ModelFraming to_framing(const FramingArgs& args) {
  ModelFraming f;
  f.light_size = args.light_size;
  f.light_height = args.light_height;
  f.up = parse_model_up(args.up);
  return f;
}

}  // namespace penumbra::cli
