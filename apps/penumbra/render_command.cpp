// `penumbra render`: one frame, one or more methods, images + stats + a comparison table.
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>

#include "commands.hpp"
#include "method_args.hpp"
#include "penumbra/core/error.hpp"
#include "penumbra/metrics/error_map.hpp"
#include "penumbra/pipeline/outputs.hpp"
#include "penumbra/report/summary_table.hpp"
#include "penumbra/scene/scene_file.hpp"

namespace penumbra::cli {

namespace {

struct RenderArgs {
  std::string scene;
  std::vector<std::string> methods;
  int samples = 16;
  std::string pattern = "grid";
  uint64_t seed = 1;
  std::string size;
  std::vector<std::string> sets;
  std::string out;
  std::string float_format = "exr";
  std::vector<std::string> aovs;
  std::string shading = "modulate";
  FramingArgs framing;
};

void write_json(const std::filesystem::path& path, const nlohmann::json& j) {
  std::ofstream f(path);
  f << j.dump(2) << "\n";
  if (!f) throw Error("cannot write " + path.string());
}

void run_render(const RenderArgs& args) {
  Scene scene = load_scene(args.scene, to_framing(args.framing));
  if (!args.size.empty()) parse_size(args.size, scene.camera);
  const SamplePattern pattern = parse_pattern(args.pattern);
  const ShadingMode shading =
      args.shading == "integrate" ? ShadingMode::integrate : ShadingMode::modulate;
  const FloatFormat format = args.float_format == "pfm" ? FloatFormat::pfm : FloatFormat::exr;

  const std::vector<const MethodInfo*> methods = selected_methods(args.methods);
  const std::vector<MethodOptions> options = resolve_method_options(methods, args.sets);

  const std::filesystem::path out_dir = args.out;
  std::error_code ec;
  std::filesystem::create_directories(out_dir, ec);
  if (ec) throw Error("cannot create output folder " + out_dir.string() + ": " + ec.message());

  LightSampleSpec spec;
  spec.pattern = pattern;
  spec.k = args.samples;
  spec.seed = args.seed;
  std::fprintf(stderr, "scene '%s': %zu triangles, %zu light(s), %dx%d, %d light samples (%s)\n",
               scene.name.c_str(), scene.triangle_count(), scene.lights.size(), scene.camera.width,
               scene.camera.height, spec.k * spec.k, args.pattern.c_str());
  const Frame frame(scene, spec);
  if (!args.aovs.empty()) write_aovs(out_dir, frame.gbuffer(), args.aovs, format);

  const bool several = methods.size() > 1;
  std::optional<MethodResult> exact;
  std::vector<TableRow> rows;
  for (size_t m = 0; m < methods.size(); ++m) {
    std::fprintf(stderr, "  %-16s ...", methods[m]->name.c_str());
    std::fflush(stderr);
    MethodResult result = frame.run(*methods[m], options[m], shading == ShadingMode::integrate);
    std::fprintf(stderr, "\r  %-16s %10.1f ms\n", methods[m]->name.c_str(), result.total_ms);

    const std::filesystem::path dir = several ? out_dir / result.method : out_dir;
    std::filesystem::create_directories(dir, ec);
    std::optional<ErrorStats> error;
    if (exact) {
      error = compare_results(frame, *exact, result);
      const Image<float> mask = surface_mask(frame.gbuffer());
      write_error_map_png(dir / "error_vs_exact.png", result_difference(*exact, result),
                          std::max(error->max_abs, 1.0 / 255.0), &mask);
    }
    std::vector<const Visibility*> per_light;
    for (const Visibility& v : result.per_light) per_light.push_back(&v);
    write_png_rgb(dir / "beauty.png", shade(frame, per_light, shading));
    write_visibility(dir, frame, result, format);
    nlohmann::json stats = stats_json(frame, result, error ? &*error : nullptr);
    stats["shading"] = std::string(to_string(shading));
    write_json(dir / "stats.json", stats);

    rows.push_back({result.method, result.total_ms, error, ""});
    if (result.method == "exact") exact = std::move(result);
  }
  if (several) {
    const std::string table = format_summary(rows, frame, std::string(to_string(shading)));
    std::printf("%s", table.c_str());
    std::ofstream(out_dir / "summary.md") << table;
    write_json(out_dir / "summary.json", table_json(rows, frame));
  }
}

}  // namespace

void add_render_command(CLI::App& app) {
  auto args = std::make_shared<RenderArgs>();
  CLI::App* cmd = app.add_subcommand("render", "Render a scene with one or more shadow methods");
  cmd->add_option("--scene", args->scene,
                  "Built-in scene name, scene .json file or model file (OBJ, PLY, glTF, ...)")
      ->required();
  cmd->add_option("--method", args->methods, "Method name (repeatable) or 'all'")->required();
  cmd->add_option("--samples", args->samples, "K: K×K light samples per pixel (1 = light centre)")
      ->check(CLI::Range(1, 64));
  cmd->add_option(
      "--pattern", args->pattern,
      "Light-sample pattern: grid, stratified, decorrelated, interleaved, halton, poisson");
  cmd->add_option("--seed", args->seed, "Seed of the random sample patterns");
  cmd->add_option("--size", args->size, "Image size WxH (overrides the scene's camera)");
  cmd->add_option("--set", args->sets, "Method option, method.option=value (repeatable)");
  cmd->add_option("--out", args->out, "Output folder")->required();
  cmd->add_option("--float-format", args->float_format, "Float image format")
      ->check(CLI::IsMember({"exr", "pfm"}));
  cmd->add_option("--aov", args->aovs,
                  "G-buffer layers to write: position,normal,shading_normal,depth,uv,mesh_id")
      ->delimiter(',');
  cmd->add_option("--shading", args->shading,
                  "modulate (V_coef × unshadowed, eq. 4.3) or integrate (per-sample, eq. 4.6)")
      ->check(CLI::IsMember({"modulate", "integrate"}));
  add_framing_options(*cmd, args->framing);
  cmd->callback([args] { run_render(*args); });
}

}  // namespace penumbra::cli
