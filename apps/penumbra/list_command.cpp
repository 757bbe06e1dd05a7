// `penumbra list`: methods with their options, built-in scenes, light-sample patterns.
// `penumbra list --markdown`: each method's option table between the markers the method pages
// hold, so that scripts/doc-options.sh can check the pages against the declarations.
#include <cstdio>
#include <memory>
#include <string>

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

/// "≥ 1", "0 … 4096" or "any" for a numeric option's declared inclusive range.
std::string range_text(const OptionSpec& o) {
  const bool has_min = o.min > -1e299, has_max = o.max < 1e299;
  const auto num = [](double v) {
    char b[32];
    std::snprintf(b, sizeof b, "%.10g", v);
    return std::string(b);
  };
  if (has_min && has_max) return num(o.min) + " … " + num(o.max);
  if (has_min) return "≥ " + num(o.min);
  if (has_max) return "≤ " + num(o.max);
  return "any";
}

std::string values_text(const OptionSpec& o) {
  switch (o.type) {
    case OptionType::boolean:
      return "`true`, `false`";
    case OptionType::choice: {
      std::string list;
      for (const std::string& c : o.choices) list += (list.empty() ? "`" : ", `") + c + "`";
      return list;
    }
    default:
      return range_text(o);
  }
}

/// A table cell: '|' would end the cell, a newline the row.
std::string cell(const std::string& text) {
  std::string out;
  for (char c : text) {
    if (c == '|')
      out += "\\|";
    else
      out += c == '\n' ? ' ' : c;
  }
  return out;
}

void print_markdown_options() {
  bool first = true;
  for (const MethodInfo& m : MethodRegistry::builtin().methods()) {
    std::printf("%s<!-- options:begin %s -->\n", first ? "" : "\n", m.name.c_str());
    first = false;
    if (m.options.empty()) {
      std::printf("`%s` has no options.\n", m.name.c_str());
    } else {
      std::printf("| option (`--set %s.KEY=VALUE`) | type | default | values | what it does |\n",
                  m.name.c_str());
      std::printf("|---|---|---|---|---|\n");
      for (const OptionSpec& o : m.options)
        std::printf("| `%s` | %s | `%s` | %s | %s |\n", o.key.c_str(), type_name(o.type),
                    o.default_value.c_str(), cell(values_text(o)).c_str(), cell(o.help).c_str());
    }
    std::printf("<!-- options:end -->\n");
  }
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
  auto markdown = std::make_shared<bool>(false);
  cmd->add_flag("--markdown", *markdown,
                "Print each method's options as a Markdown table between the "
                "<!-- options:begin METHOD --> / <!-- options:end --> markers of docs/methods/");
  cmd->callback([markdown] { *markdown ? print_markdown_options() : run_list(); });
}

}  // namespace penumbra::cli
