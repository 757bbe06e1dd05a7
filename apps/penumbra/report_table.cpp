#include "report_table.hpp"

#include <cstdio>

namespace penumbra::cli {

namespace {

const TableRow* find_row(const std::vector<TableRow>& rows, const std::string& name) {
  for (const TableRow& r : rows)
    if (r.method == name) return &r;
  return nullptr;
}

std::string fmt(const char* format, double value) {
  char buf[64];
  std::snprintf(buf, sizeof buf, format, value);
  return buf;
}

}  // namespace

std::string format_table(const std::vector<TableRow>& rows) {
  const TableRow* rt = find_row(rows, "raytrace");
  std::string out =
      "| method | time (ms) | speed vs raytrace | mean abs (shadowed) | mean abs | max abs | rmse "
      "| > 1/255 |\n"
      "|---|---:|---:|---:|---:|---:|---:|---:|\n";
  for (const TableRow& r : rows) {
    out += "| " + r.method + " | " + fmt("%.1f", r.ms) + " | ";
    out += rt && r.ms > 0.0 ? fmt("%.2fx", rt->ms / r.ms) : std::string("-");
    if (r.vs_exact) {
      const ErrorStats& e = *r.vs_exact;
      out += " | " + fmt("%.5f", e.mean_abs_shadowed) + " | " + fmt("%.5f", e.mean_abs) + " | " +
             fmt("%.4f", e.max_abs) + " | " + fmt("%.5f", e.rmse) + " | " +
             fmt("%.4f", e.frac_over_1_255) + " |\n";
    } else {
      out += r.method == "exact" ? " | (reference) | | | | |\n" : " | - | - | - | - | - |\n";
    }
  }
  return out;
}

nlohmann::json table_json(const std::vector<TableRow>& rows, const Frame& frame) {
  const TableRow* rt = find_row(rows, "raytrace");
  nlohmann::json methods = nlohmann::json::array();
  for (const TableRow& r : rows) {
    nlohmann::json j = {{"method", r.method}, {"time_ms", r.ms}};
    if (rt && r.ms > 0.0) j["speed_vs_raytrace"] = rt->ms / r.ms;
    if (r.vs_exact) j["error_vs_exact"] = to_json(*r.vs_exact);
    methods.push_back(j);
  }
  return {{"scene", frame.scene().name},
          {"width", frame.gbuffer().width},
          {"height", frame.gbuffer().height},
          {"samples", frame.samples().count()},
          {"methods", methods}};
}

}  // namespace penumbra::cli
