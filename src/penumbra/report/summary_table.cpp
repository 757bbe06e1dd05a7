#include "penumbra/report/summary_table.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace penumbra {

namespace {

const TableRow* find_row(const std::vector<TableRow>& rows, const std::string& name) {
  for (const TableRow& r : rows)
    if (r.method == name && r.failure.empty()) return &r;
  return nullptr;
}

std::string fmt(const char* format, double value) {
  char buf[64];
  std::snprintf(buf, sizeof buf, format, value);
  return buf;
}

}  // namespace

std::string summary_header(const Frame& frame, const std::string& shading) {
  const LightSampleSpec& spec = frame.samples().spec();
  const Scene& scene = frame.scene();
  return "Scene `" + scene.name + "`, " + std::to_string(frame.gbuffer().width) + "×" +
         std::to_string(frame.gbuffer().height) + " pixels, " + std::to_string(spec.k) + "×" +
         std::to_string(spec.k) + " = " + std::to_string(frame.samples().count()) +
         " light samples (`" + std::string(to_string(spec.pattern)) + "` pattern, seed " +
         std::to_string(spec.seed) + "), " + std::to_string(scene.lights.size()) + " light(s), " +
         std::to_string(scene.triangle_count()) + " triangles, shading `" + shading + "`.\n";
}

double equal_time_rays(int samples, double raytrace_ms, double method_ms) {
  return raytrace_ms > 0.0 ? samples * method_ms / raytrace_ms : std::nan("");
}

std::string format_table(const std::vector<TableRow>& rows, int samples) {
  const TableRow* rt = find_row(rows, "raytrace");
  const bool temporal = std::any_of(rows.begin(), rows.end(),
                                    [](const TableRow& r) { return r.temporal_error.has_value(); });
  std::string out =
      "| method | time (ms) | speed vs raytrace | rays in same time | mean abs (shadowed) | "
      "mean abs | max abs | rmse | > 1/255 |";
  out += temporal ? " temporal |\n" : "\n";
  out += "|---|---:|---:|---:|---:|---:|---:|---:|---:|";
  out += temporal ? "---:|\n" : "\n";
  for (const TableRow& r : rows) {
    if (!r.failure.empty()) {
      out += "| " + r.method + " | failed: " + r.failure + " | | | | | | | |";
      out += temporal ? " |\n" : "\n";
      continue;
    }
    out += "| " + r.method + " | " + fmt("%.1f", r.ms) + " | ";
    out += rt && r.ms > 0.0 ? fmt("%.2fx", rt->ms / r.ms) : std::string("-");
    out += " | ";
    out += rt ? fmt("%.0f", equal_time_rays(samples, rt->ms, r.ms)) : std::string("-");
    if (r.vs_exact) {
      const ErrorStats& e = *r.vs_exact;
      out += " | " + fmt("%.5f", e.mean_abs_shadowed) + " | " + fmt("%.5f", e.mean_abs) + " | " +
             fmt("%.4f", e.max_abs) + " | " + fmt("%.5f", e.rmse) + " | " +
             fmt("%.4f", e.frac_over_1_255) + " |";
    } else {
      out += r.reference ? " | (reference) | | | | |" : " | - | - | - | - | - |";
    }
    if (temporal) {
      out += ' ';
      out += r.temporal_error ? fmt("%.5f", *r.temporal_error) : std::string("-");
      out += " |";
    }
    out += "\n";
  }
  return out;
}

std::string reference_v(const std::string& reference) {
  return reference == "exact" ? "V_exact" : "V_ref";
}

std::string table_column_key(const std::string& reference) {
  const std::string v_ref = reference_v(reference);
  return "- **time**: the method's own time for every light of the frame, in milliseconds (the "
         "shared BVH and G-buffer excluded); wall-clock, so it varies with the machine's load.\n"
         "- **speed vs raytrace**: `raytrace` time / method time, both from this run "
         "(> 1 = faster than Embree).\n"
         "- **rays in same time**: rays per pixel `raytrace` traces in the method's time (its own "
         "samples × method time / `raytrace` time): the light sampling ray tracing affords at the "
         "method's frame rate [Wang 2014 Table 11].\n"
         "- Errors are against `" +
         reference +
         "`, on the visible fraction V of each light (0 = umbra, 1 = lit), over the surface "
         "pixels of every light:\n"
         "  **mean abs (shadowed)** = mean |V − " +
         v_ref + "| over the pixels `" + reference +
         "` puts in umbra or penumbra [Atty 2006 §4.2.1]; **mean abs** = over every surface pixel; "
         "**max abs** = "
         "worst pixel; **rmse** = root mean square; **> 1/255** = fraction of pixels whose error "
         "shows in an 8-bit image.\n";
}

std::string format_summary(const std::vector<TableRow>& rows, const Frame& frame,
                           const std::string& shading, const std::string& reference) {
  return summary_header(frame, shading) + "\n" + format_table(rows, frame.samples().count()) +
         "\n" + table_column_key(reference);
}

nlohmann::json table_json(const std::vector<TableRow>& rows, const Frame& frame) {
  const TableRow* rt = find_row(rows, "raytrace");
  nlohmann::json methods = nlohmann::json::array();
  for (const TableRow& r : rows) {
    nlohmann::json j = {{"method", r.method}};
    if (!r.failure.empty()) {
      j["failure"] = r.failure;
    } else {
      j["time_ms"] = r.ms;
      if (rt && r.ms > 0.0) j["speed_vs_raytrace"] = rt->ms / r.ms;
      if (rt && rt->ms > 0.0)
        j["equal_time_rays"] = equal_time_rays(frame.samples().count(), rt->ms, r.ms);
      if (r.vs_exact) j["error_vs_exact"] = to_json(*r.vs_exact);
      if (r.temporal_error) j["temporal_error"] = *r.temporal_error;
    }
    methods.push_back(j);
  }
  const LightSampleSpec& spec = frame.samples().spec();
  return {{"scene", frame.scene().name},
          {"width", frame.gbuffer().width},
          {"height", frame.gbuffer().height},
          {"samples", frame.samples().count()},
          {"pattern", std::string(to_string(spec.pattern))},
          {"methods", methods}};
}

}  // namespace penumbra
