// The comparison table printed by `penumbra render --method ...` with several methods.
#pragma once

#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "penumbra/metrics/error_metrics.hpp"
#include "penumbra/pipeline/frame.hpp"

namespace penumbra::cli {

struct TableRow {
  std::string method;
  double ms = 0.0;
  std::optional<ErrorStats> vs_exact;  // absent for `exact` itself or when exact was not run
};

/// A Markdown table: method, time, speed relative to `raytrace` of the same run, error vs exact.
std::string format_table(const std::vector<TableRow>& rows);
nlohmann::json table_json(const std::vector<TableRow>& rows, const Frame& frame);

}  // namespace penumbra::cli
