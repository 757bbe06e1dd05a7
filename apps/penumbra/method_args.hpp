// Command-line arguments shared by `render` and `report`: --size, --set, --method, --pattern.
#pragma once

#include <CLI/CLI.hpp>
#include <map>
#include <string>
#include <vector>

#include "penumbra/core/light_samples.hpp"
#include "penumbra/scene/camera.hpp"
#include "penumbra/scene/model_scene.hpp"
#include "penumbra/shadows/registry.hpp"

namespace penumbra::cli {

/// --size WxH into the camera; throws Error for anything else.
void parse_size(const std::string& text, Camera& camera);

/// --set method.key=value, grouped by method.
std::map<std::string, std::map<std::string, std::string>> parse_sets(
    const std::vector<std::string>& sets);

/// The methods named (or `all`), `exact` first, each once.
std::vector<const MethodInfo*> selected_methods(const std::vector<std::string>& names);

/// Every method's options with the --set values applied (resolved before any frame runs, so bad
/// options fail fast); warns about --set for a method that is not rendered.
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
