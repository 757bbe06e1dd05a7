// `penumbra render`: one frame, one or more methods, images + stats + a comparison table.
#include <tbb/task_group.h>
#include <unistd.h>

#include <chrono>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>

#include "commands.hpp"
#include "method_args.hpp"
#include "penumbra/core/error.hpp"
#include "penumbra/core/files.hpp"
#include "penumbra/core/progress.hpp"
#include "penumbra/core/stats.hpp"
#include "penumbra/pipeline/outputs.hpp"
#include "penumbra/report/sequence_run.hpp"
#include "penumbra/report/summary_table.hpp"
#include "penumbra/scene/scene_file.hpp"

#ifdef PENUMBRA_HAVE_VULKAN
#include "penumbra/gpu/backend.hpp"
#endif

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
  std::string backend = "cpu";
  std::string vk_device;  // empty: $PENUMBRA_VK_DEVICE, else the first discrete GPU
  FramingArgs framing;
  std::string frames;  // --frames START:END[:STEP]: a sequence (render_sequence.hpp)
  double fps = 0.0;    // --fps: overrides the scene's frame rate
};

#ifdef PENUMBRA_HAVE_VULKAN
/// --backend vulkan: opens the device and binds every method to it; fails before the frame when
/// the device or a method's Vulkan path is missing.
std::unique_ptr<gpu::Backend> open_vulkan(const RenderArgs& args,
                                          std::vector<const MethodInfo*>& methods,
                                          std::vector<MethodInfo>& bound) {
  for (const MethodInfo* m : methods)
    if (!gpu::Backend::supports(m->name)) {
      std::string list;
      for (const std::string& n : gpu::Backend::methods()) list += (list.empty() ? "" : ", ") + n;
      throw Error("--backend vulkan: method '" + m->name + "' has no Vulkan implementation (" +
                  list + " have one)");
    }
  gpu::ContextOptions options;
  options.device = args.vk_device;
  auto backend = std::make_unique<gpu::Backend>(options);
  bound.reserve(methods.size());
  for (const MethodInfo*& m : methods) m = &bound.emplace_back(backend->vulkan_method(*m));
  return backend;
}
#endif

/// Memory available to this process: MemAvailable from /proc/meminfo, else physical memory.
uint64_t available_memory_bytes() {
  std::ifstream meminfo("/proc/meminfo");
  std::string key;
  uint64_t kb = 0;
  std::string unit;
  while (meminfo >> key >> kb >> unit)
    if (key == "MemAvailable:") return kb * 1024;
  const long pages = ::sysconf(_SC_PHYS_PAGES), page = ::sysconf(_SC_PAGE_SIZE);
  return pages > 0 && page > 0 ? static_cast<uint64_t>(pages) * static_cast<uint64_t>(page) : 0;
}

/// Peak memory of a render, estimated before anything is allocated: per pixel the G-buffer
/// (64 bytes), per light its receiver classes and unshadowed irradiance (13), per method and light
/// its visibility and the exact reference kept for comparison (8), the images written (beauty,
/// EXR layers, error map: ~40), and with `integrate` the light-sample masks (k² bits per light).
/// Measured: `render --scene quad --method raytrace --method shadow_map --samples 2 --size
/// 1024x1024` peaks at 135 MB resident; this estimates 148 MB.
uint64_t estimate_render_bytes(const Camera& camera, size_t lights, size_t methods, int k,
                               bool masks) {
  const uint64_t pixels = static_cast<uint64_t>(camera.width) * camera.height;
  uint64_t per_pixel = 64 + 40 + lights * (13 + 8 * (methods + 1));
  if (masks) per_pixel += lights * 2 * ((static_cast<uint64_t>(k) * k + 63) / 64) * 8;
  return pixels * per_pixel;
}

/// Refuses, with a clear message, a render that cannot fit in memory (rather than failing with
/// bad_alloc or the OOM killer part-way through).
void check_memory(const RenderArgs& args, const Camera& camera, size_t lights, size_t methods,
                  bool masks) {
  const uint64_t need = estimate_render_bytes(camera, lights, methods, args.samples, masks);
  const uint64_t have = available_memory_bytes();
  if (have == 0 || need <= have) return;
  char text[200];
  std::snprintf(text, sizeof text,
                "a %dx%d frame needs about %.1f GB (estimated) and %.1f GB are available: use a "
                "smaller --size",
                camera.width, camera.height, static_cast<double>(need) / 1e9,
                static_cast<double>(have) / 1e9);
  throw Error(text);
}

/// The frame's size when --size gives a valid one (an invalid one is left to parse_size after the
/// load, so that the scene's own errors still come first).
std::optional<Camera> size_option(const std::string& size) {
  if (size.empty()) return std::nullopt;
  Camera camera;
  try {
    parse_size(size, camera);
  } catch (const Error&) {
    return std::nullopt;
  }
  return camera;
}

void write_json(const std::filesystem::path& path, const nlohmann::json& j) {
  write_text_file(path, j.dump(2) + "\n");
}

/// Where the whole process's time went, in the order it was spent: stats.json's "frame" block and
/// the breakdown line printed at the end. Every stage is wall time on the main thread; other_ms is
/// the rest of elapsed_ms (CLI parsing, the checks of Frame::run's results, stats.json). Not in
/// it: the dynamic loader before static initialisation and the exit after the last stats.json.
/// Work run beside a stage is inside that stage's wall time and listed apart, in "overlapped",
/// never added to the sum.
struct ProcessCosts {
  double startup_ms = 0.0;         // static initialisation → the render command's start
  double load_ms = 0.0;            // the scene and its meshes
  double gbuffer_layers_ms = 0.0;  // the G-buffer's allocation (with --size), beside the load,
                                   // setup and BVH build
  double setup_ms = 0.0;           // methods, options, memory check, output folder
  double aovs_ms = 0.0;            // --aov files
  double methods_ms = 0.0;  // every Frame::run so far (the methods' own times and their checks)
  double outputs_ms = 0.0;  // every method's comparison, images and stats so far

  /// The CLI's entries of the "frame" block; stats_json (outputs.hpp) wrote the frame's own.
  void add_to(nlohmann::json& frame) const {
    frame["startup_ms"] = startup_ms;
    frame["load_ms"] = load_ms;
    frame["setup_ms"] = setup_ms;
    if (aovs_ms > 0.0) frame["aovs_ms"] = aovs_ms;
    frame["methods_ms"] = methods_ms;
    frame["outputs_ms"] = outputs_ms;
    if (gbuffer_layers_ms > 0.0) frame["overlapped"]["gbuffer_layers_ms"] = gbuffer_layers_ms;
    const double elapsed = elapsed_ms(process_start());
    double accounted = 0.0;
    for (const auto& [key, value] : frame.items())
      if (value.is_number() && key != "other_ms" && key != "elapsed_ms")
        accounted += value.get<double>();
    frame["other_ms"] = std::max(0.0, elapsed - accounted);
    frame["elapsed_ms"] = elapsed;
  }
};

/// One line: each stage of the "frame" block, in the order spent.
void print_costs(const nlohmann::json& frame) {
  static const std::pair<const char*, const char*> kStages[] = {
      {"startup_ms", "startup"},     {"load_ms", "load"},
      {"setup_ms", "setup"},         {"embree_device_ms", "Embree device"},
      {"bvh_build_ms", "BVH"},       {"gbuffer_ms", "G-buffer"},
      {"receivers_ms", "receivers"}, {"irradiance_ms", "irradiance"},
      {"aovs_ms", "AOVs"},           {"methods_ms", "methods"},
      {"outputs_ms", "outputs"},     {"other_ms", "other"}};
  // Overlapped work, after the last stage it ran beside: {stage, {overlapped key, text}}.
  static const std::pair<const char*, std::pair<const char*, const char*>> kBeside[] = {
      {"bvh_build_ms", {"gbuffer_layers_ms", "beside load to BVH: G-buffer layers"}},
      {"methods_ms", {"irradiance_background_ms", "beside them: irradiance"}}};
  std::string line = "frame:";
  for (const auto& [key, name] : kStages)
    if (frame.contains(key)) {
      char part[96];
      std::snprintf(part, sizeof part, "%s %s %.0f", line.size() > 6 ? " +" : "", name,
                    frame[key].get<double>());
      line += part;
      for (const auto& [stage, beside] : kBeside)
        if (stage == std::string_view(key) && frame.contains("overlapped") &&
            frame["overlapped"].contains(beside.first)) {
          std::snprintf(part, sizeof part, " (%s %.0f)", beside.second,
                        frame["overlapped"][beside.first].get<double>());
          line += part;
        }
    }
  std::fprintf(stderr, "%s = %.0f ms (stats.json \"frame\")\n", line.c_str(),
               frame["elapsed_ms"].get<double>());
}

void run_render(const RenderArgs& args) {
  const auto command_start = std::chrono::steady_clock::now();
  ProcessCosts costs;
  costs.startup_ms =
      std::chrono::duration<double, std::milli>(command_start - process_start()).count();
  // Every argument is checked before the scene is read: a typo is reported at once, not after
  // a long load.
  const SamplePattern pattern = parse_pattern(args.pattern);
  std::vector<const MethodInfo*> methods = selected_methods(args.methods);
  const std::vector<MethodOptions> options = resolve_method_options(methods, args.sets);
  const std::vector<std::string> aovs = split_aovs(args.aovs);
  std::optional<FrameRange> range;
  if (!args.frames.empty()) range = parse_frame_range(args.frames);
  if (args.fps > 0.0 && !range) throw Error("--fps applies to a sequence: give --frames too");
  if (range && !aovs.empty()) throw Error("--aov writes one frame's G-buffer: not with --frames");
  // With --size the G-buffer's size is known before the scene: its layers (64 bytes a pixel,
  // mostly the first touch of their pages) are allocated by a task of their own while this thread
  // reads the scene and builds the BVH, on whichever core is free — unless they alone would take
  // half the memory left (check_memory then refuses the frame with its message, below). The Frame
  // waits for them before the primary rays.
  GBuffer layers;
  tbb::task_group layers_task;
  const std::optional<Camera> sized = size_option(args.size);
  const bool layers_beside =
      !range && sized &&
      64 * static_cast<uint64_t>(sized->width) * sized->height < available_memory_bytes() / 2;
  if (layers_beside)
    layers_task.run([&] {
      const auto start = std::chrono::steady_clock::now();
      layers = background_gbuffer(sized->width, sized->height);
      costs.gbuffer_layers_ms = elapsed_ms(start);
    });
  Scene scene = load_scene(args.scene, to_framing(args.framing));
  costs.load_ms = elapsed_ms(command_start);
  const auto setup_start = std::chrono::steady_clock::now();
  if (!args.size.empty()) parse_size(args.size, scene.camera);
  const ShadingMode shading =
      args.shading == "integrate" ? ShadingMode::integrate : ShadingMode::modulate;
  const FloatFormat format = args.float_format == "pfm" ? FloatFormat::pfm : FloatFormat::exr;

  std::string device_name = "cpu";
#ifdef PENUMBRA_HAVE_VULKAN
  std::vector<MethodInfo> vulkan_methods;
  std::unique_ptr<gpu::Backend> backend;
  if (args.backend == "vulkan") {
    backend = open_vulkan(args, methods, vulkan_methods);
    device_name = backend->context().device_name();
    std::fprintf(stderr, "vulkan device: %s\n", device_name.c_str());
  }
#else
  if (args.backend == "vulkan")
    throw Error(
        "--backend vulkan: this build has no Vulkan backend (install libvulkan-dev and "
        "glslc, then rebuild)");
#endif
  check_memory(args, scene.camera, scene.lights.size(), methods.size(),
               shading == ShadingMode::integrate);

  const std::filesystem::path out_dir = args.out;
  std::error_code ec;
  std::filesystem::create_directories(out_dir, ec);
  if (ec)
    throw Error("cannot create output folder " + quote(out_dir.string(), 200) + ": " +
                ec.message());

  costs.setup_ms = elapsed_ms(setup_start);

  LightSampleSpec spec;
  spec.pattern = pattern;
  spec.k = args.samples;
  spec.seed = args.seed;
  std::fprintf(stderr, "scene '%s': %zu triangles, %zu light(s), %dx%d, %d light samples (%s)\n",
               scene.name.c_str(), scene.triangle_count(), scene.lights.size(), scene.camera.width,
               scene.camera.height, spec.k * spec.k, args.pattern.c_str());
  if (range) {
    SequenceJob job{*range, args.fps, {},           spec,       shading,
                    format, out_dir,  args.backend, device_name};
    for (size_t m = 0; m < methods.size(); ++m) job.methods.push_back({methods[m], options[m]});
    render_sequence(scene, job);
    return;
  }
  const Frame frame(scene, spec, [&] {
    if (layers_beside) layers_task.wait();
    return std::move(layers);
  });
  // Shared by every method's beauty image, and independent of the methods: computed beside the
  // method at the lowest priority, finished after it (irradiance_ms), so that outputs_ms is the
  // writing only. Only when one method runs: methods compared in one process are each timed with
  // nothing beside them (their ratios are the tables' figures); then it is computed after the
  // first, on all cores.
  if (methods.size() == 1) frame.start_unshadowed_in_background();
  if (!aovs.empty()) {
    const auto aovs_start = std::chrono::steady_clock::now();
    write_aovs(out_dir, frame.gbuffer(), aovs, format);
    costs.aovs_ms = elapsed_ms(aovs_start);
  }

  const bool several = methods.size() > 1;
  nlohmann::json last_frame;
  std::optional<MethodResult> exact;
  std::vector<TableRow> rows;
  for (size_t m = 0; m < methods.size(); ++m) {
    char line[128];
    std::snprintf(line, sizeof line, "  %-16s", methods[m]->name.c_str());
    begin_status_line(line);
    const auto run_start = std::chrono::steady_clock::now();
    MethodResult result = frame.run(*methods[m], options[m], shading == ShadingMode::integrate);
    costs.methods_ms += elapsed_ms(run_start);
    std::snprintf(line, sizeof line, "  %-16s %10.1f ms", methods[m]->name.c_str(),
                  result.total_ms);
    end_status_line(line);
    for (size_t l = 0; l < scene.lights.size(); ++l) frame.unshadowed(l);

    const auto outputs_start = std::chrono::steady_clock::now();
    const std::filesystem::path dir = several ? out_dir / result.method : out_dir;
    std::optional<ErrorStats> error;
    nlohmann::json stats =
        write_method_frame(dir, frame, result, exact ? &*exact : nullptr, shading, format, error);
    stats["backend"] = args.backend;
    stats["device"] = device_name;
    // The whole process so far: every method run so far and their outputs, this one's included.
    costs.outputs_ms += elapsed_ms(outputs_start);
    costs.add_to(stats["frame"]);
    write_json(dir / "stats.json", stats);
    if (m + 1 == methods.size()) last_frame = stats["frame"];

    rows.push_back(
        {result.method, result.total_ms, error, "", result.method == "exact", std::nullopt});
    if (result.method == "exact") exact = std::move(result);
  }
  if (several) {
    const std::string table = format_summary(rows, frame, std::string(to_string(shading)));
    std::printf("%s", table.c_str());
    write_text_file(out_dir / "summary.md", table);
    write_json(out_dir / "summary.json", table_json(rows, frame));
  }
  print_costs(last_frame);
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
      ->transform(base10_integer(1, 64));
  cmd->add_option(
      "--pattern", args->pattern,
      "Light-sample pattern: grid, stratified, decorrelated, interleaved, halton, poisson");
  cmd->add_option("--seed", args->seed, "Seed of the random sample patterns")
      ->transform(base10_integer(0, std::numeric_limits<uint64_t>::max()));
  cmd->add_option("--size", args->size, "Image size WxH (overrides the scene's camera)")
      ->transform(size_value());
  cmd->add_option("--set", args->sets, "Method option, method.option=value (repeatable)");
  cmd->add_option("--out", args->out, "Output folder")->required();
  cmd->add_option("--float-format", args->float_format, "Float image format")
      ->check(CLI::IsMember({"exr", "pfm"}));
  cmd->add_option("--aov", args->aovs,
                  "G-buffer layers to write: position,normal,shading_normal,depth,uv,mesh_id");
  cmd->add_option("--shading", args->shading,
                  "modulate (V_coef × unshadowed, eq. 4.3) or integrate (per-sample, eq. 4.6)")
      ->check(CLI::IsMember({"modulate", "integrate"}));
  cmd->add_option("--backend", args->backend,
                  "Where the methods run: cpu, or vulkan (gears, dcs, wedges, wedge_blend, ssm, "
                  "silhouette_map, shadow_map, pcss and shadow_volume on the GPU)")
      ->check(CLI::IsMember({"cpu", "vulkan"}));
  cmd->add_option("--vk-device", args->vk_device,
                  "Vulkan device: index or name substring (default $PENUMBRA_VK_DEVICE, else the "
                  "first discrete GPU, else the first device)");
  cmd->add_option("--frames", args->frames,
                  "START:END[:STEP]: render these frames of the scene's animation "
                  "(OUT/<method>/frame_NNNN/, frames.json, frames.csv, videos with ffmpeg)");
  cmd->add_option("--fps", args->fps, "Frame rate of --frames (default: the scene's)")
      ->check(CLI::PositiveNumber & CLI::Range(1e-3, 1e4));
  add_framing_options(*cmd, args->framing);
  cmd->callback([args] { run_render(*args); });
}

}  // namespace penumbra::cli
