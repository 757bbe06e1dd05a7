// `penumbra compare REF TEST`: error metrics between two visibility files, plus an error map.
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>

#include "commands.hpp"
#include "method_args.hpp"
#include "penumbra/core/error.hpp"
#include "penumbra/core/files.hpp"
#include "penumbra/io/image_io.hpp"
#include "penumbra/metrics/error_map.hpp"
#include "penumbra/metrics/error_metrics.hpp"

namespace penumbra::cli {

namespace {

struct CompareArgs {
  std::string ref, test, out;
  double error_scale = 0.0;
};

/// Visibility layers of a file: "light<l>" (EXR from render), or the single grey layer of a PFM.
bool is_light_layer(const std::string& name) {
  return name.size() > 5 && name.compare(0, 5, "light") == 0 &&
         std::all_of(name.begin() + 5, name.end(), [](char c) { return c >= '0' && c <= '9'; });
}

std::vector<FloatLayer> light_layers(const std::vector<FloatLayer>& layers) {
  std::vector<FloatLayer> out;
  for (const FloatLayer& l : layers)
    if (is_light_layer(l.name)) out.push_back(l);
  if (out.empty() && layers.size() == 1) out.push_back(layers.front());
  return out;
}

std::optional<Image<float>> mask_of(const std::filesystem::path& file,
                                    const std::vector<FloatLayer>& layers) {
  for (const FloatLayer& l : layers)
    if (l.name == "mask") return l.pixels;
  const std::filesystem::path pfm_mask = file.parent_path() / "mask.pfm";
  if (file.extension() == ".pfm" && std::filesystem::exists(pfm_mask))
    return read_float_image(pfm_mask).front().pixels;
  return std::nullopt;
}

/// The scene recorded in the stats.json beside a rendered visibility file, or "".
std::string recorded_scene(const std::filesystem::path& file) {
  const std::filesystem::path stats = file.parent_path() / "stats.json";
  if (!regular_file_problem(stats).empty()) return "";
  try {
    std::ifstream in(stats);
    const nlohmann::json j = nlohmann::json::parse(in);
    return j.at("scene").at("name").get<std::string>();
  } catch (const std::exception&) {
    return "";  // not ours or unreadable: nothing to warn about
  }
}

void run_compare(const CompareArgs& args) {
  const auto ref_all = read_float_image(args.ref);
  const auto test_all = read_float_image(args.test);
  const auto ref = light_layers(ref_all), test = light_layers(test_all);
  if (ref.empty())
    throw Error(quote(args.ref, 200) +
                ": no visibility layer (expected light0, light1, ... or one grey channel)");
  if (ref.size() != test.size())
    throw Error("the files hold different numbers of lights (" + std::to_string(ref.size()) +
                " vs " + std::to_string(test.size()) + ")");
  const Image<float>& r0 = ref.front().pixels;
  const Image<float>& t0 = test.front().pixels;
  if (r0.width() != t0.width() || r0.height() != t0.height())
    throw Error("cannot compare images of different sizes: " + quote(args.ref, 200) + " is " +
                std::to_string(r0.width()) + "x" + std::to_string(r0.height()) + ", " +
                quote(args.test, 200) + " is " + std::to_string(t0.width()) + "x" +
                std::to_string(t0.height()) + " (render both with the same --size)");
  const std::string ref_scene = recorded_scene(args.ref), test_scene = recorded_scene(args.test);
  if (!ref_scene.empty() && !test_scene.empty() && ref_scene != test_scene)
    std::fprintf(stderr, "penumbra: warning: comparing renders of different scenes (%s vs %s)\n",
                 quote(ref_scene).c_str(), quote(test_scene).c_str());
  const std::optional<Image<float>> mask = mask_of(args.ref, ref_all);

  nlohmann::json j;
  nlohmann::json per_light = nlohmann::json::array();
  ErrorStats first{};
  for (size_t l = 0; l < ref.size(); ++l) {
    const ErrorStats e = compare_images(ref[l].pixels, test[l].pixels, mask ? &*mask : nullptr);
    if (l == 0) first = e;
    per_light.push_back(to_json(e));
  }
  j = to_json(first);
  if (ref.size() > 1) j["lights"] = per_light;
  for (const auto& [key, value] : j.items())
    if (key != "lights") std::printf("%-18s %s\n", key.c_str(), value.dump().c_str());

  if (!args.out.empty()) {
    const std::filesystem::path dir = args.out;
    std::error_code ec;
    std::filesystem::create_directories(dir, ec);
    if (ec)
      throw Error("cannot create output folder " + quote(dir.string(), 200) + ": " + ec.message());
    write_text_file(dir / "compare.json", j.dump(2) + "\n");
    const double scale =
        args.error_scale > 0.0 ? args.error_scale : std::max(first.max_abs, 1.0 / 255.0);
    write_error_map_png(dir / "error_map.png", abs_difference(ref[0].pixels, test[0].pixels), scale,
                        mask ? &*mask : nullptr);
  }
}

}  // namespace

void add_compare_command(CLI::App& app) {
  auto args = std::make_shared<CompareArgs>();
  CLI::App* cmd = app.add_subcommand(
      "compare", "Compare two visibility files (EXR or PFM) and map their error");
  cmd->add_option("REF", args->ref, "Reference visibility file (e.g. exact/visibility.exr)")
      ->required();
  cmd->add_option("TEST", args->test, "Visibility file to judge")->required();
  cmd->add_option("--out", args->out, "Folder for compare.json and error_map.png");
  cmd->add_option("--error-scale", args->error_scale,
                  "Error mapped to the top of the colour scale (default: max error)")
      ->transform(positive_finite());
  cmd->callback([args] { run_compare(*args); });
}

}  // namespace penumbra::cli
