#include "penumbra/shadows/registry.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>

#include "penumbra/core/error.hpp"

namespace penumbra {

namespace {

std::string known_keys(const MethodInfo& info) {
  std::string s;
  for (const OptionSpec& o : info.options) s += (s.empty() ? "" : ", ") + o.key;
  return s.empty() ? "none" : s;
}

/// Checks `text` against the option's type and range; returns the normalised text.
std::string check_value(const MethodInfo& info, const OptionSpec& spec, const std::string& text) {
  const std::string who = info.name + "." + spec.key;
  switch (spec.type) {
    case OptionType::integer:
    case OptionType::real: {
      char* end = nullptr;
      const double value = std::strtod(text.c_str(), &end);
      if (text.empty() || *end != '\0' || !std::isfinite(value))
        throw Error(who + ": '" + text + "' is not a number");
      if (spec.type == OptionType::integer && value != std::floor(value))
        throw Error(who + ": '" + text + "' is not an integer");
      if (value < spec.min || value > spec.max)
        throw Error(who + ": " + text + " is outside [" + std::to_string(spec.min) + ", " +
                    std::to_string(spec.max) + "]");
      return text;
    }
    case OptionType::boolean:
      if (text == "true" || text == "1" || text == "on") return "true";
      if (text == "false" || text == "0" || text == "off") return "false";
      throw Error(who + ": '" + text + "' is not a boolean (true/false)");
    case OptionType::choice:
      if (std::find(spec.choices.begin(), spec.choices.end(), text) == spec.choices.end()) {
        std::string list;
        for (const auto& c : spec.choices) list += (list.empty() ? "" : ", ") + c;
        throw Error(who + ": '" + text + "' is not one of " + list);
      }
      return text;
  }
  return text;
}

}  // namespace

const std::string& MethodOptions::raw(const std::string& key) const {
  const auto it = values_.find(key);
  if (it == values_.end()) throw Error("internal: undeclared option '" + key + "'");
  return it->second;
}

int MethodOptions::get_int(const std::string& key) const {
  return static_cast<int>(std::strtol(raw(key).c_str(), nullptr, 10));
}
double MethodOptions::get_real(const std::string& key) const {
  return std::strtod(raw(key).c_str(), nullptr);
}
bool MethodOptions::get_bool(const std::string& key) const {
  return raw(key) == "true";
}
const std::string& MethodOptions::get_choice(const std::string& key) const {
  return raw(key);
}

MethodOptions resolve_options(const MethodInfo& info,
                              const std::map<std::string, std::string>& overrides) {
  MethodOptions out;
  for (const OptionSpec& spec : info.options)
    out.values_[spec.key] = check_value(info, spec, spec.default_value);
  for (const auto& [key, text] : overrides) {
    const auto it = std::find_if(info.options.begin(), info.options.end(),
                                 [&](const OptionSpec& o) { return o.key == key; });
    if (it == info.options.end())
      throw Error("method '" + info.name + "' has no option '" + key +
                  "' (options: " + known_keys(info) + ")");
    out.values_[key] = check_value(info, *it, text);
  }
  return out;
}

void MethodRegistry::add(MethodInfo info) {
  methods_.push_back(std::move(info));
}

const MethodInfo* MethodRegistry::find(std::string_view name) const {
  for (const MethodInfo& m : methods_)
    if (m.name == name) return &m;
  return nullptr;
}

const MethodInfo& MethodRegistry::get(std::string_view name) const {
  if (const MethodInfo* m = find(name)) return *m;
  std::string list;
  for (const MethodInfo& m : methods_) list += (list.empty() ? "" : ", ") + m.name;
  throw Error("unknown method '" + std::string(name) + "' (known: " + list + ")");
}

const MethodRegistry& MethodRegistry::builtin() {
  static const MethodRegistry registry = [] {
    MethodRegistry r;
    register_exact(r);
    register_raytrace(r);
    register_gears(r);
    register_dcs(r);
    register_shadow_volume(r);
    register_shadow_map(r);
    register_pcss(r);
    register_wedges(r);
    register_wedge_blend(r);
    register_ssm(r);
    register_silhouette_map(r);
    return r;
  }();
  return registry;
}

}  // namespace penumbra
