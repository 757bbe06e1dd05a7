// `penumbra list`: methods with their options, built-in scenes, light-sample patterns.
#include <cstdio>

#include "commands.hpp"
#include "penumbra/core/light_samples.hpp"
#include "penumbra/scene/builtin_scenes.hpp"
#include "penumbra/shadows/registry.hpp"

namespace penumbra::cli {

namespace {

const char* type_name(OptionType t) {
  switch (t) {
    case OptionType::integer:
      return "int";
    case OptionType::real:
      return "real";
    case OptionType::boolean:
      return "bool";
    case OptionType::choice:
      return "choice";
  }
  return "?";
}

void run_list() {
  std::printf("methods:\n");
  for (const MethodInfo& m : MethodRegistry::builtin().methods()) {
    std::printf("  %-16s %s%s\n", m.name.c_str(), m.summary.c_str(),
                m.sample_exact ? " [sample-exact]" : "");
    std::printf("  %-16s %s\n", "", m.reference.c_str());
    for (const OptionSpec& o : m.options) {
      std::string extra;
      for (const std::string& c : o.choices) extra += (extra.empty() ? " {" : ", ") + c;
      if (!extra.empty()) extra += "}";
      std::printf("    --set %s.%s=%s  (%s%s) %s\n", m.name.c_str(), o.key.c_str(),
                  o.default_value.c_str(), type_name(o.type), extra.c_str(), o.help.c_str());
    }
  }
  std::printf("scenes:\n");
  for (const BuiltinSceneInfo& s : builtin_scenes())
    std::printf("  %-16s %s%s\n", s.name.c_str(), s.description.c_str(),
                s.needs_models ? " (scripts/fetch-models.sh)" : "");
  std::printf("light-sample patterns (--pattern):\n ");
  for (SamplePattern p : all_sample_patterns())
    std::printf(" %s", std::string(to_string(p)).c_str());
  std::printf("\n");
}

}  // namespace

void add_list_command(CLI::App& app) {
  CLI::App* cmd = app.add_subcommand(
      "list", "List methods (with options), built-in scenes and sample patterns");
  cmd->callback(run_list);
}

}  // namespace penumbra::cli
