// The comparison table of one frame (method, time, speed against `raytrace` of the same run,
// error against `exact`), as Markdown with a header and a column key, and as JSON. Printed by
// `penumbra render` with several methods (summary.md) and by `penumbra report` (results.md).
#pragma once

#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "penumbra/metrics/error_metrics.hpp"
#include "penumbra/pipeline/frame.hpp"

namespace penumbra {

struct TableRow {
  std::string method;
  double ms = 0.0;
  std::optional<ErrorStats> vs_exact;  // against the reference; absent for the reference itself
  std::string failure;                 // the method's error message when it could not run
  bool reference = false;              // the row every error is measured against
  /// A frame sequence's mean temporal error against the reference (pipeline/sequence.hpp); a
  /// table with any row holding one gets a `temporal` column.
  std::optional<double> temporal_error;
};

/// What the table is about, one line: scene, size, light samples and pattern, shading.
std::string summary_header(const Frame& frame, const std::string& shading);

/// A Markdown table: method, time, speed relative to `raytrace` of the same run, the rays per
/// pixel `raytrace` traces in the method's time (`samples` rays per pixel in its own), error vs
/// the reference.
std::string format_table(const std::vector<TableRow>& rows, int samples);

/// Rays per pixel `raytrace` (tracing `samples` rays per pixel in `raytrace_ms`) traces in
/// `method_ms`: the light-sampling resolution ray tracing affords at the method's frame rate
/// [Wang 2014 Table 11]. NaN without a positive raytrace time.
double equal_time_rays(int samples, double raytrace_ms, double method_ms);

/// The reference's V in formulas: V_exact for `exact`, V_ref for any other reference.
std::string reference_v(const std::string& reference);

/// What each column of format_table means (Markdown list); `reference` names what the errors are
/// against (`exact`, or e.g. `raytrace 64×64`).
std::string table_column_key(const std::string& reference = "exact");

/// Header, table and column key: the whole summary.md.
std::string format_summary(const std::vector<TableRow>& rows, const Frame& frame,
                           const std::string& shading, const std::string& reference = "exact");

/// The table as JSON; rows hold time_ms, speed_vs_raytrace and error_vs_exact.
nlohmann::json table_json(const std::vector<TableRow>& rows, const Frame& frame);

}  // namespace penumbra
