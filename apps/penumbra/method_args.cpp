#include "method_args.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <optional>
#include <string_view>
#include <system_error>

#include "penumbra/core/error.hpp"
#include "penumbra/core/suggest.hpp"
#include "penumbra/pipeline/outputs.hpp"

namespace penumbra::cli {

namespace {

/// `text` whole as a base-10 unsigned integer (std::from_chars: no sign, blanks, hex or octal).
std::optional<uint64_t> parse_base10(std::string_view text) {
  uint64_t value = 0;
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value, 10);
  if (text.empty() || ec != std::errc{} || end != text.data() + text.size()) return std::nullopt;
  return value;
}

}  // namespace

void parse_size(const std::string& text, Camera& camera) {
  const size_t x = text.find_first_of("xX");
  const std::optional<uint64_t> w =
      x == std::string::npos ? std::nullopt : parse_base10(text.substr(0, x));
  const std::optional<uint64_t> h =
      x == std::string::npos ? std::nullopt : parse_base10(text.substr(x + 1));
  if (!w || !h || *w < 1 || *h < 1 || *w > 16384 || *h > 16384)
    throw Error("--size: expected WxH with 1..16384 pixels each, got " + quote(text));
  camera.width = static_cast<int>(*w);
  camera.height = static_cast<int>(*h);
}

CLI::Validator size_value() {
  return CLI::Validator(
      [](std::string& text) {
        Camera unused;
        try {
          parse_size(text, unused);
        } catch (const Error& e) {
          return std::string(e.what()).substr(std::string("--size: ").size());
        }
        return std::string();
      },
      "WxH");
}

CLI::Validator base10_integer(uint64_t lo, uint64_t hi) {
  return CLI::Validator(
      [lo, hi](std::string& text) {
        const std::optional<uint64_t> value = parse_base10(text);
        if (!value)
          return quote(text) + " is not a base-10 integer in [" + std::to_string(lo) + ", " +
                 std::to_string(hi) + "]";
        if (*value < lo || *value > hi)
          return std::to_string(*value) + " is outside [" + std::to_string(lo) + ", " +
                 std::to_string(hi) + "]";
        text = std::to_string(*value);  // CLI11 reads a leading 0 as octal: no leading zeros
        return std::string();
      },
      "INT in [" + std::to_string(lo) + " - " + std::to_string(hi) + "]");
}

CLI::Validator positive_finite() {
  return CLI::Validator(
      [](std::string& text) {
        double value = 0.0;
        const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value,
                                               std::chars_format::general);
        if (text.empty() || ec != std::errc{} || end != text.data() + text.size() ||
            !std::isfinite(value) || !(value > 0.0))
          return quote(text) + " is not a finite number > 0";
        return std::string();
      },
      "POSITIVE");
}

std::vector<std::string> split_aovs(const std::vector<std::string>& values) {
  std::string known;
  for (const std::string& n : aov_names()) known += (known.empty() ? "" : ", ") + n;
  std::vector<std::string> out;
  for (const std::string& value : values) {
    size_t begin = 0;
    while (true) {
      const size_t comma = value.find(',', begin);
      const std::string name =
          value.substr(begin, comma == std::string::npos ? std::string::npos : comma - begin);
      if (name.empty())
        throw Error("--aov: an empty AOV name in " + quote(value) + " (known: " + known + ")");
      if (std::find(aov_names().begin(), aov_names().end(), name) == aov_names().end())
        throw Error("--aov: unknown AOV " + quote(name) + did_you_mean(name, aov_names()) +
                    " (known: " + known + ")");
      if (std::find(out.begin(), out.end(), name) == out.end()) out.push_back(name);
      if (comma == std::string::npos) break;
      begin = comma + 1;
    }
  }
  return out;
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
    // Every --set is checked against its method's declaration, rendered or not: a typo in a
    // value is an error even when that method is left out of this run.
    const MethodInfo& info = MethodRegistry::builtin().get(name);  // unknown method → error
    resolve_options(info, values);
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
  if (!pattern) {
    std::vector<std::string> names;
    for (const SamplePattern p : all_sample_patterns()) names.emplace_back(to_string(p));
    std::string list;
    for (const std::string& n : names) list += (list.empty() ? "" : ", ") + n;
    throw Error("--pattern: unknown light-sample pattern " + quote(name) +
                did_you_mean(name, names) + " (patterns: " + list + ")");
  }
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
