// `penumbra report`: every method × scene in one process, one self-contained HTML page.
#include <cstdio>
#include <memory>

#include "commands.hpp"
#include "method_args.hpp"
#include "penumbra/core/error.hpp"
#include "penumbra/report/report.hpp"

namespace penumbra::cli {

namespace {

struct ReportArgs {
  std::vector<std::string> scenes;
  std::vector<std::string> methods;
  int samples = 16;
  std::string pattern = "grid";
  uint64_t seed = 1;
  std::string size;
  std::vector<std::string> sets;
  std::vector<std::string> sweeps;
  double error_scale = 0.0;
  std::string reference = "exact";
  int reference_samples = 64;
  std::string out;
};

/// The command that reproduces the report, from the parsed arguments (defaults included).
std::string command_line(const ReportArgs& a) {
  std::string c = "penumbra report";
  for (const std::string& s : a.scenes) c += " --scene " + s;
  for (const std::string& m : a.methods) c += " --method " + m;
  if (!a.size.empty()) c += " --size " + a.size;
  c += " --samples " + std::to_string(a.samples) + " --pattern " + a.pattern;
  if (a.seed != 1) c += " --seed " + std::to_string(a.seed);
  for (const std::string& s : a.sets) c += " --set " + s;
  for (const std::string& s : a.sweeps) c += " --sweep " + s;
  if (a.error_scale > 0.0) c += " --error-scale " + std::to_string(a.error_scale);
  if (a.reference != "exact")
    c += " --reference " + a.reference + " --reference-samples " +
         std::to_string(a.reference_samples);
  return c + " --out " + a.out;
}

void run_report(const ReportArgs& args) {
  report::ReportSpec spec;
  spec.scenes = args.scenes;
  spec.methods = selected_methods(args.methods);
  spec.options = resolve_method_options(spec.methods, args.sets);
  if (!args.size.empty()) {
    Camera c;
    parse_size(args.size, c);
    spec.size = std::make_pair(c.width, c.height);
  }
  spec.samples.pattern = parse_pattern(args.pattern);
  spec.samples.k = args.samples;
  spec.samples.seed = args.seed;
  spec.sweeps = args.sweeps;
  spec.error_scale = args.error_scale;
  spec.reference = args.reference;
  spec.reference_k = args.reference_samples;
  spec.command_line = command_line(args);
  spec.out_dir = args.out;
  const std::filesystem::path index = report::write_report(spec);
  std::printf("%s\n", index.string().c_str());
}

}  // namespace

void add_report_command(CLI::App& app) {
  auto args = std::make_shared<ReportArgs>();
  CLI::App* cmd = app.add_subcommand(
      "report", "Render every method on every scene and write one self-contained HTML report");
  cmd->add_option("--scene", args->scenes,
                  "Scene: built-in name, scene .json or model file (repeatable)")
      ->required();
  cmd->add_option("--method", args->methods,
                  "Method name (repeatable) or 'all'; exact is always run when it is the reference")
      ->required();
  cmd->add_option("--samples", args->samples, "K: K×K light samples per pixel (1 = light centre)")
      ->check(CLI::Range(1, 64))
      ->capture_default_str();
  cmd->add_option(
         "--pattern", args->pattern,
         "Light-sample pattern: grid, stratified, decorrelated, interleaved, halton, poisson")
      ->capture_default_str();
  cmd->add_option("--seed", args->seed, "Seed of the random sample patterns")
      ->capture_default_str();
  cmd->add_option("--size", args->size, "Image size WxH (overrides every scene's camera)");
  cmd->add_option("--set", args->sets, "Method option, method.option=value (repeatable)");
  cmd->add_option("--sweep", args->sweeps,
                  "Sweep on the first scene: samples, light_size, resolution (repeatable)")
      ->check(CLI::IsMember(report::sweep_names()));
  cmd->add_option("--error-scale", args->error_scale,
                  "Error at the top of every error map's colour scale (default: per scene, the "
                  "median over the methods of their 99th-percentile error)")
      ->check(CLI::PositiveNumber);
  cmd->add_option("--reference", args->reference,
                  "What errors are measured against: exact (the analytic integral) or raytrace "
                  "(Embree with --reference-samples², for scenes where exact is too slow)")
      ->check(CLI::IsMember({"exact", "raytrace"}))
      ->capture_default_str();
  cmd->add_option("--reference-samples", args->reference_samples,
                  "K: the raytrace reference's K×K light samples (same pattern and seed)")
      ->check(CLI::Range(1, 64))
      ->capture_default_str();
  cmd->add_option("--out", args->out, "Output folder (index.html, report.json, results.md)")
      ->required();
  cmd->callback([args] { run_report(*args); });
}

}  // namespace penumbra::cli
