// `penumbra view`: the scene in a window, the method recomputed as the light and camera move.
#include "../commands.hpp"
#include "../method_args.hpp"
#include "penumbra/core/error.hpp"
#include "penumbra/scene/scene_file.hpp"
#include "viewer.hpp"

namespace penumbra::cli {

namespace {

struct ViewArgs {
  viewer::ViewerArgs viewer;
  std::vector<std::string> sets;
  FramingArgs framing;
};

void run_view(ViewArgs& args) {
  // Everything the user typed is checked before the window opens.
  Scene scene = load_scene(args.viewer.scene, to_framing(args.framing));
  if (!args.viewer.size.empty()) parse_size(args.viewer.size, scene.camera);
  parse_pattern(args.viewer.pattern);
  if (!args.viewer.method.empty()) {
    const std::vector<const MethodInfo*> methods = selected_methods({args.viewer.method});
    if (methods.size() != 1) throw Error("view: --method takes one method, not 'all'");
    args.viewer.method = methods.front()->name;
  }
  for (const auto& [method, values] : parse_sets(args.sets)) {
    resolve_options(MethodRegistry::builtin().get(method), values);  // bad value → Error
    args.viewer.options[method] = values;
  }
  std::vector<viewer::ScriptCommand> script;
  if (!args.viewer.script.empty()) script = viewer::read_script(args.viewer.script);
  viewer::run_viewer(args.viewer, std::move(scene), std::move(script));
}

}  // namespace

void add_view_command(CLI::App& app) {
  auto args = std::make_shared<ViewArgs>();
  CLI::App* cmd = app.add_subcommand(
      "view", "Show a scene in a window: move the light and camera, switch methods, see errors");
  cmd->add_option("--scene", args->viewer.scene,
                  "Built-in scene name, scene .json file or model file (OBJ, PLY, glTF, ...)")
      ->required();
  cmd->add_option("--method", args->viewer.method,
                  "The method shown first (default: exact; with --backend vulkan, gears)");
  cmd->add_option("--backend", args->viewer.backend,
                  "Where the methods run: cpu, or vulkan (those with a Vulkan path; the reference "
                  "stays on the CPU)")
      ->check(CLI::IsMember({"cpu", "vulkan"}));
  cmd->add_option("--vk-device", args->viewer.vk_device,
                  "Vulkan device: index or name substring (as for render)");
  cmd->add_option("--size", args->viewer.size, "Full image size WxH (overrides the scene's)");
  cmd->add_option("--samples", args->viewer.samples,
                  "K: K×K light samples per pixel (1 = light centre)")
      ->check(CLI::Range(1, 64));
  cmd->add_option("--pattern", args->viewer.pattern,
                  "Light-sample pattern: grid, stratified, decorrelated, interleaved, halton, "
                  "poisson");
  cmd->add_option("--seed", args->viewer.seed, "Seed of the random sample patterns");
  cmd->add_option("--set", args->sets, "Method option, method.option=value (repeatable)");
  cmd->add_option("--script", args->viewer.script,
                  "Run the commands of FILE, one per line, then exit (docs/viewer.md)");
  cmd->add_option("--preview-divisor", args->viewer.preview_divisor,
                  "While the user drags, frames are this many times smaller on each side "
                  "(1: always full size)")
      ->check(CLI::Range(1, 64));
  cmd->add_option("--settle-ms", args->viewer.settle_ms,
                  "Milliseconds without an edit after which the full-size frame is computed")
      ->check(CLI::Range(0.0, 10000.0));
  cmd->add_option("--reference", args->viewer.reference,
                  "What the error views compare against: exact, or raytrace with "
                  "--reference-samples² samples (for scenes where exact is too slow)")
      ->check(CLI::IsMember({"exact", "raytrace"}));
  cmd->add_option("--reference-samples", args->viewer.reference_samples,
                  "K: the raytrace reference's K×K light samples")
      ->check(CLI::Range(1, 64));
  cmd->add_flag("--trace", args->viewer.trace,
                "Print one line per frame shown: where its time went, and its latency");
  add_framing_options(*cmd, args->framing);
  cmd->callback([args] { run_view(*args); });
}

}  // namespace penumbra::cli
