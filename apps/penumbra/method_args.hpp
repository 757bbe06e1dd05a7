// Command-line arguments shared by `render` and `report`: --size, --set, --method, --pattern.
#pragma once

#include <CLI/CLI.hpp>
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "penumbra/core/light_samples.hpp"
#include "penumbra/scene/camera.hpp"
#include "penumbra/scene/model_scene.hpp"
#include "penumbra/shadows/registry.hpp"

namespace penumbra::cli {

/// --size WxH into the camera (base-10 W and H in 1..16384); throws Error for anything else.
void parse_size(const std::string& text, Camera& camera);

/// CLI11 validators (for ->transform: CLI11's own integer reading takes hex, octal and negative
/// numbers modulo 2⁶⁴, and an empty value as 0):
/// --size: what parse_size accepts, the empty string included as an error.
CLI::Validator size_value();
/// A base-10 integer in [lo, hi], the whole value; rewritten without leading zeros.
CLI::Validator base10_integer(uint64_t lo, uint64_t hi);
/// A finite number > 0 (no nan, inf, empty or negative value).
CLI::Validator positive_finite();

/// --aov values (each a comma-separated list) as one list of known names, each once; throws
/// Error naming an empty or unknown name.
std::vector<std::string> split_aovs(const std::vector<std::string>& values);

/// --set method.key=value, grouped by method.
std::map<std::string, std::map<std::string, std::string>> parse_sets(
    const std::vector<std::string>& sets);

/// The methods named (or `all`), `exact` first, each once.
std::vector<const MethodInfo*> selected_methods(const std::vector<std::string>& names);

/// Every method's options with the --set values applied (resolved before any frame runs, so bad
/// options fail fast); every --set is checked against its method's options, and a --set for a
/// method that is not rendered is also warned about.
std::vector<MethodOptions> resolve_method_options(const std::vector<const MethodInfo*>& methods,
                                                  const std::vector<std::string>& sets);

/// --pattern NAME; throws Error for an unknown pattern.
SamplePattern parse_pattern(const std::string& name);

/// --light-size, --light-height, --up: how a model file given as --scene is framed.
struct FramingArgs {
  float light_size = ModelFraming{}.light_size;
  float light_height = ModelFraming{}.light_height;
  std::string up = "auto";
};
void add_framing_options(CLI::App& cmd, FramingArgs& args);
ModelFraming to_framing(const FramingArgs& args);

}  // namespace penumbra::cli
