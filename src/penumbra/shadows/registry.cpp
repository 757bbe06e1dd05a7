#include "penumbra/shadows/registry.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <limits>
#include <system_error>

#include "penumbra/core/error.hpp"
#include "penumbra/core/suggest.hpp"

namespace penumbra {

namespace {

std::string known_keys(const MethodInfo& info) {
  std::string s;
  for (const OptionSpec& o : info.options) s += (s.empty() ? "" : ", ") + o.key;
  return s.empty() ? "none" : s;
}

std::string shortest(double value) {
  char buf[32];
  const auto [end, ec] = std::to_chars(buf, buf + sizeof buf, value);
  return ec == std::errc{} ? std::string(buf, end) : std::to_string(value);
}

/// Parses `text` once, whole string, base 10 (`std::from_chars`: no hex, no exponent for integers,
/// no leading '+' or blanks), checks type and range, and returns the parsed value with its
/// canonical text (what stats.json records).
OptionValue check_value(const MethodInfo& info, const OptionSpec& spec, const std::string& text) {
  const std::string who = info.name + "." + spec.key;
  const std::string shown = quote(text);
  const char* first = text.data();
  const char* last = text.data() + text.size();
  OptionValue out;
  switch (spec.type) {
    case OptionType::integer: {
      long long value = 0;
      const auto [end, ec] = std::from_chars(first, last, value, 10);
      if (text.empty() || ec != std::errc{} || end != last)
        throw Error(who + ": " + shown + " is not a base-10 integer");
      out.real = static_cast<double>(value);
      out.integer = value;
      out.text = std::to_string(value);
      break;
    }
    case OptionType::real: {
      double value = 0.0;
      const auto [end, ec] = std::from_chars(first, last, value, std::chars_format::general);
      if (text.empty() || ec != std::errc{} || end != last || !std::isfinite(value))
        throw Error(who + ": " + shown + " is not a finite number");
      out.real = value;
      out.text = shortest(value);
      break;
    }
    case OptionType::boolean:
      if (text == "true" || text == "1" || text == "on")
        out.text = "true";
      else if (text == "false" || text == "0" || text == "off")
        out.text = "false";
      else
        throw Error(who + ": " + shown + " is not a boolean (true/false)");
      out.integer = out.text == "true";
      return out;
    case OptionType::choice:
      if (std::find(spec.choices.begin(), spec.choices.end(), text) == spec.choices.end()) {
        std::string list;
        for (const auto& c : spec.choices) list += (list.empty() ? "" : ", ") + c;
        throw Error(who + ": " + shown + " is not one of " + list);
      }
      out.text = text;
      return out;
  }
  if (out.real < spec.min || out.real > spec.max)
    throw Error(who + ": " + out.text + " is outside [" + shortest(spec.min) + ", " +
                shortest(spec.max) + "]");
  return out;
}

}  // namespace

const OptionValue& MethodOptions::parsed(const std::string& key) const {
  const auto it = parsed_.find(key);
  if (it == parsed_.end()) throw Error("internal: undeclared option '" + key + "'");
  return it->second;
}

int MethodOptions::get_int(const std::string& key) const {
  const long long value = parsed(key).integer;
  // Declared ranges keep integers small; a range wider than int is a declaration bug.
  if (value < std::numeric_limits<int>::min() || value > std::numeric_limits<int>::max())
    throw Error("internal: option '" + key + "' does not fit an int");
  return static_cast<int>(value);
}
double MethodOptions::get_real(const std::string& key) const {
  return parsed(key).real;
}
bool MethodOptions::get_bool(const std::string& key) const {
  return parsed(key).integer != 0;
}
const std::string& MethodOptions::get_choice(const std::string& key) const {
  return parsed(key).text;
}

void MethodOptions::set(const std::string& key, OptionValue value) {
  values_[key] = value.text;
  parsed_[key] = std::move(value);
}

MethodOptions resolve_options(const MethodInfo& info,
                              const std::map<std::string, std::string>& overrides) {
  MethodOptions out;
  for (const OptionSpec& spec : info.options)
    out.set(spec.key, check_value(info, spec, spec.default_value));
  for (const auto& [key, text] : overrides) {
    const auto it = std::find_if(info.options.begin(), info.options.end(),
                                 [&](const OptionSpec& o) { return o.key == key; });
    if (it == info.options.end())
      throw Error("method '" + info.name + "' has no option " + quote(key) +
                  " (options: " + known_keys(info) + ")");
    out.set(key, check_value(info, *it, text));
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
  std::vector<std::string> names;
  for (const MethodInfo& m : methods_) {
    list += (list.empty() ? "" : ", ") + m.name;
    names.push_back(m.name);
  }
  throw Error("unknown method " + quote(name) + did_you_mean(name, names) + " (known: " + list +
              ")");
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
