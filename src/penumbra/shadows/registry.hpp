// Methods by name, each with typed, documented options (settable from the CLI as
// --set method.option=value). Options are declared once, with their defaults, in the method's
// MethodInfo.
#pragma once

#include <functional>
#include <map>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "penumbra/shadows/method.hpp"

namespace penumbra {

enum class OptionType { integer, real, boolean, choice };

struct OptionSpec {
  std::string key;
  OptionType type = OptionType::integer;
  std::string default_value;
  std::string help;
  std::vector<std::string> choices;  // OptionType::choice
  double min = -1e300;               // integer, real: inclusive range
  double max = 1e300;
};

/// One option value, parsed once when it is resolved.
struct OptionValue {
  std::string text;       // canonical text: what stats.json records
  double real = 0.0;      // integer and real options
  long long integer = 0;  // integer options; 1/0 for booleans
};

/// Validated option values of one method.
class MethodOptions {
 public:
  int get_int(const std::string& key) const;
  double get_real(const std::string& key) const;
  bool get_bool(const std::string& key) const;
  const std::string& get_choice(const std::string& key) const;
  const std::map<std::string, std::string>& values() const { return values_; }

 private:
  friend MethodOptions resolve_options(const struct MethodInfo&,
                                       const std::map<std::string, std::string>&);
  const OptionValue& parsed(const std::string& key) const;
  void set(const std::string& key, OptionValue value);
  std::map<std::string, std::string> values_;  // canonical texts, for the records
  std::map<std::string, OptionValue> parsed_;
};

struct MethodInfo {
  std::string name;
  std::string summary;
  std::string reference;      // paper and section, e.g. "[Wang 2014 §3]"
  bool sample_exact = false;  // same per-sample answer as raytrace on the same light samples
  std::vector<OptionSpec> options;
  std::function<std::unique_ptr<ShadowMethod>(const MethodOptions&)> create;
};

/// Applies `overrides` (key -> text) to the declared defaults; throws Error for an unknown key or
/// a value of the wrong type or out of range.
MethodOptions resolve_options(const MethodInfo& info,
                              const std::map<std::string, std::string>& overrides);

class MethodRegistry {
 public:
  /// Every method Penumbra implements, in presentation order.
  static const MethodRegistry& builtin();

  void add(MethodInfo info);
  const MethodInfo* find(std::string_view name) const;
  const MethodInfo& get(std::string_view name) const;  // throws Error listing the known names
  const std::vector<MethodInfo>& methods() const { return methods_; }

 private:
  std::vector<MethodInfo> methods_;
};

// One registration function per method (shadows/<method>.cpp), called by builtin().
void register_raytrace(MethodRegistry& registry);
void register_exact(MethodRegistry& registry);
void register_gears(MethodRegistry& registry);
void register_shadow_volume(MethodRegistry& registry);
void register_shadow_map(MethodRegistry& registry);
void register_pcss(MethodRegistry& registry);
void register_wedges(MethodRegistry& registry);
void register_wedge_blend(MethodRegistry& registry);
void register_ssm(MethodRegistry& registry);
void register_silhouette_map(MethodRegistry& registry);
void register_dcs(MethodRegistry& registry);

}  // namespace penumbra
