// `penumbra report`: every method × scene rendered in one process, written as one self-contained
// HTML page (index.html, its PNGs beside it, SVG charts inline; no script or style from the
// network), plus report.json (every number of the page) and results.md (the Markdown tables
// docs/results.md is made from).
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "penumbra/core/light_samples.hpp"
#include "penumbra/shadows/registry.hpp"

namespace penumbra::report {

struct ReportSpec {
  std::vector<std::string> scenes;          // built-in names or scene/model files
  std::vector<const MethodInfo*> methods;   // `exact` is added first when it is the reference
  std::vector<MethodOptions> options;       // one per method
  std::optional<std::pair<int, int>> size;  // overrides every scene's camera
  LightSampleSpec samples;
  /// Sweeps run on the first scene: "samples" (K×K), "light_size" (×0.25..2), "resolution".
  std::vector<std::string> sweeps;
  double error_scale = 0.0;  // 0: common_error_scale per scene
  /// What every error is measured against: "exact" (the analytic integral over the light), or
  /// "raytrace" with reference_k × reference_k light samples of the same pattern, for scenes
  /// where `exact` takes too long (foliage, fragmented geometry: docs/methods/exact.md).
  std::string reference = "exact";
  int reference_k = 64;
  std::string command_line;  // shown in the header, so the page says how to reproduce it
  std::filesystem::path out_dir;
};

/// A reference's name for people: `exact`, or `raytrace K×K` (`reference` "raytrace" with
/// `k` × `k` samples). The report and the viewer name their reference so.
std::string reference_label(const std::string& reference, int k);

/// The sweeps `penumbra report --sweep` knows.
const std::vector<std::string>& sweep_names();

/// Renders everything and writes out_dir/{index.html, report.json, results.md,
/// error_vs_time.svg, <scene>/*.png}.
/// Returns the path of index.html. A method that throws Error on a scene gets a "failed" row
/// with the message; a scene that cannot be loaded is an Error.
std::filesystem::path write_report(const ReportSpec& spec);

}  // namespace penumbra::report
