// What `penumbra report` measured, as the page, report.json and results.md read it.
#pragma once

#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "penumbra/metrics/error_metrics.hpp"
#include "penumbra/report/machine.hpp"
#include "penumbra/report/report_images.hpp"

namespace penumbra::report {

struct MethodEntry {
  std::string method;
  std::string failure;  // non-empty: the method threw this message on this scene
  double ms = 0.0;
  std::optional<ErrorStats> vs_exact;  // against the scene's reference (first method)
  std::vector<std::pair<std::string, double>> stages;  // stats.json times_ms, without "total"
  nlohmann::json stats;                                // the method's stats.json
};

struct SceneEntry {
  std::string name;
  std::string folder;          // relative to the report folder
  std::string reference;       // what errors are against: `exact` or e.g. `raytrace 64×64`
  std::string summary_header;  // summary_table.hpp's one-line description
  std::string results_md;      // header, table and key
  int width = 0, height = 0;
  nlohmann::json frame;  // the frame's shared stages (stats.json "frame"), read generically
  double error_scale = 0.0;
  CropRect crop;
  int crop_zoom = 1;
  std::vector<MethodEntry> methods;  // the reference first

  const MethodEntry* find(const std::string& method) const {
    for (const MethodEntry& m : methods)
      if (m.method == method && m.failure.empty()) return &m;
    return nullptr;
  }
};

struct SweepCurve {
  std::string method;
  std::vector<double> error;  // mean abs (shadowed) against the reference, per x
  std::vector<double> ms;
};

struct SweepEntry {
  std::string name, scene, x_label;
  std::vector<double> x;
  std::vector<SweepCurve> curves;
};

struct ReportData {
  MachineInfo machine;
  std::string command_line;
  std::string samples;    // "16×16 grid"
  std::string reference;  // `exact` or e.g. `raytrace 64×64`
  std::vector<SceneEntry> scenes;
  std::vector<SweepEntry> sweeps;
};

/// The page: index.html's whole text.
std::string report_html(const ReportData& data);
/// The across-scenes error-against-time chart, a standalone SVG (error_vs_time.svg, and inline in
/// the page): what docs/choosing.md shows.
std::string error_vs_time_svg(const ReportData& data);
/// Everything as JSON (report.json).
nlohmann::json report_json(const ReportData& data);
/// The Markdown results (results.md): header, then per scene its summary table.
std::string report_markdown(const ReportData& data);

}  // namespace penumbra::report
