// index.html, report.json and results.md from the measured ReportData.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>

#include "penumbra/report/report_data.hpp"
#include "penumbra/report/summary_table.hpp"
#include "penumbra/report/svg_plot.hpp"

namespace penumbra::report {

namespace {

using plot::xml_escape;

std::string fmt(const char* format, double v) {
  char b[64];
  std::snprintf(b, sizeof b, format, v);
  return b;
}

constexpr const char* kStyle = R"css(
:root { --fg: #1d2127; --muted: #5b6470; --line: #d9dde3; --accent: #2a6fdb; --bg: #f6f7f9; }
* { box-sizing: border-box; }
body { margin: 0; font: 15px/1.45 system-ui, -apple-system, "Segoe UI", sans-serif; color: var(--fg);
       background: var(--bg); }
header.top { background: #1d2127; color: #f2f4f7; padding: 20px 32px 16px; }
header.top h1 { margin: 0 0 8px; font-size: 24px; font-weight: 650; }
header.top dl { display: grid; grid-template-columns: max-content 1fr; gap: 2px 16px; margin: 0;
                font-size: 13px; }
header.top dt { color: #a9b1bc; }
header.top dd { margin: 0; }
header.top code { color: #ffe08a; word-break: break-all; }
nav { padding: 8px 32px; background: #fff; border-bottom: 1px solid var(--line); position: sticky;
      top: 0; z-index: 2; font-size: 14px; }
nav a { margin-right: 16px; color: var(--accent); text-decoration: none; font-weight: 600; }
main { padding: 8px 32px 48px; max-width: 1800px; }
section.scene, section.across { background: #fff; border: 1px solid var(--line); border-radius: 8px;
  padding: 4px 24px 20px; margin: 20px 0; }
h2 { font-size: 21px; margin: 16px 0 4px; }
h3 { font-size: 16px; margin: 22px 0 8px; }
p.meta, p.note { color: var(--muted); margin: 4px 0; font-size: 13.5px; }
.grid { display: grid; grid-template-columns: repeat(auto-fill, minmax(220px, 1fr)); gap: 14px; }
figure { margin: 0; }
figure img { width: 100%; height: auto; display: block; border-radius: 4px; background: #303030; }
figure.crop img { image-rendering: pixelated; width: auto; max-width: 100%; }
figcaption { font-size: 13px; margin-top: 4px; }
figcaption b { font-weight: 650; }
figcaption span { color: var(--muted); }
figure.placeholder div { border: 1px dashed var(--line); border-radius: 4px; }
figure.reference img { outline: 3px solid #2a6fdb; outline-offset: -3px; }
.legend { display: flex; flex-wrap: wrap; gap: 8px 28px; align-items: center; margin: 6px 0; }
.legend svg { display: block; }
.charts { display: flex; flex-wrap: wrap; gap: 16px; }
.charts svg { max-width: 100%; height: auto; border: 1px solid var(--line); border-radius: 6px; }
table.sortable { border-collapse: collapse; font-size: 13.5px; font-variant-numeric: tabular-nums;
                 margin: 4px 0; }
table.sortable th, table.sortable td { padding: 4px 10px; border-bottom: 1px solid var(--line);
                                       text-align: right; white-space: nowrap; }
table.sortable th:first-child, table.sortable td:first-child { text-align: left; }
table.sortable th { cursor: pointer; background: #eef1f5; position: relative; user-select: none; }
table.sortable th[data-dir=asc]::after { content: " ▲"; font-size: 10px; }
table.sortable th[data-dir=desc]::after { content: " ▼"; font-size: 10px; }
table.sortable tr:hover td { background: #f5f8ff; }
td.failed { color: #b3261e; text-align: left !important; white-space: normal !important; }
.key { font-size: 13px; color: var(--muted); max-width: 1100px; }
.key li { margin: 2px 0; }
)css";

// Sorts a table by the clicked column (numbers by value, text alphabetically), and records
// on <body> how many images loaded, for the browser test and for anyone looking at the DOM.
constexpr const char* kScript = R"js(
document.querySelectorAll('table.sortable').forEach(function (table) {
  table.querySelectorAll('th').forEach(function (th, col) {
    th.addEventListener('click', function () {
      var asc = th.dataset.dir !== 'asc';
      table.querySelectorAll('th').forEach(function (h) { delete h.dataset.dir; });
      th.dataset.dir = asc ? 'asc' : 'desc';
      var body = table.tBodies[0];
      var rows = Array.prototype.slice.call(body.rows);
      rows.sort(function (a, b) {
        var x = a.cells[col].dataset.v, y = b.cells[col].dataset.v;
        var nx = parseFloat(x), ny = parseFloat(y);
        var c = (isNaN(nx) || isNaN(ny)) ? String(x).localeCompare(String(y)) : nx - ny;
        return asc ? c : -c;
      });
      rows.forEach(function (r) { body.appendChild(r); });
    });
  });
});
window.addEventListener('load', function () {
  var images = document.images, broken = 0;
  for (var i = 0; i < images.length; ++i)
    if (!images[i].complete || images[i].naturalWidth === 0) ++broken;
  document.body.dataset.images = images.length;
  document.body.dataset.imagesBroken = broken;
});
)js";

/// Errors below this are float rounding of an exact method: drawn at it on log axes.
constexpr double kErrorFloor = 1e-6;

std::vector<double> floored(std::vector<double> errors) {
  for (double& e : errors)
    if (std::isfinite(e)) e = std::max(e, kErrorFloor);
  return errors;
}

std::string img(const std::string& src, const std::string& alt, int w, int h) {
  return "<img src='" + xml_escape(src) + "' alt='" + xml_escape(alt) + "' width='" +
         std::to_string(w) + "' height='" + std::to_string(h) + "' loading='eager'>";
}

double speed_vs_raytrace(const SceneEntry& s, const MethodEntry& m) {
  const MethodEntry* rt = s.find("raytrace");
  return rt && m.ms > 0.0 ? rt->ms / m.ms : std::nan("");
}

bool is_reference(const SceneEntry& s, const MethodEntry& m) {
  return !s.methods.empty() && &m == &s.methods.front();
}

/// Rays per pixel `raytrace` traces in the method's time (summary_table.hpp).
double rays_in_same_time(const SceneEntry& s, const MethodEntry& m) {
  const MethodEntry* rt = s.find("raytrace");
  if (!rt || !rt->stats.contains("samples")) return std::nan("");
  return equal_time_rays(rt->stats["samples"]["count"].get<int>(), rt->ms, m.ms);
}

std::string caption(const SceneEntry& s, const MethodEntry& m) {
  std::string c = "<figcaption><b>" + xml_escape(m.method) + "</b> <span>";
  if (!m.failure.empty()) return c + "failed</span></figcaption>";
  c += fmt("%.1f ms", m.ms);
  const double speed = speed_vs_raytrace(s, m);
  if (std::isfinite(speed) && m.method != "raytrace") c += fmt(", %.2f× raytrace", speed);
  if (m.vs_exact) c += fmt(", err %.4f", m.vs_exact->mean_abs_shadowed);
  if (is_reference(s, m)) c += " — reference";
  return c + "</span></figcaption>";
}

std::string figure_grid(const SceneEntry& s, const std::string& suffix, bool with_exact,
                        const std::string& what, bool crop) {
  const int w = crop ? s.crop.size * s.crop_zoom : s.width;
  const int h = crop ? s.crop.size * s.crop_zoom : s.height;
  std::ostringstream o;
  o << "<div class='grid'>\n";
  for (const MethodEntry& m : s.methods) {
    if (!with_exact && is_reference(s, m)) {  // keeps every method in the beauty row's column
      o << "<figure class='placeholder'><div style='aspect-ratio:" << w << "/" << h
        << "'></div><figcaption><span>" << xml_escape(s.reference)
        << ": the reference (no error)</span></figcaption></figure>\n";
      continue;
    }
    if (!m.failure.empty()) continue;
    o << "<figure class='" << (is_reference(s, m) ? "reference" : "") << (crop ? " crop" : "")
      << "'>" << img(s.folder + "/" + m.method + suffix + ".png", m.method + " " + what, w, h)
      << caption(s, m) << "</figure>\n";
  }
  o << "</div>\n";
  return o.str();
}

std::string legends(const SceneEntry& s) {
  const double e = s.error_scale;
  const std::string scale = plot::tick_label(e);
  std::ostringstream o;
  o << "<div class='legend'>"
    << plot::color_bar_svg(abs_error_colors(), 0.0, e,
                           {{0.0, "0"}, {e / 2, plot::tick_label(e / 2)}, {e, "≥ " + scale}},
                           "|V − " + reference_v(s.reference) + "| (fraction of the light, 0–1)")
    << plot::color_bar_svg(
           signed_error_colors(), -e, e,
           {{-e, "≤ −" + scale + " (too dark)"}, {0.0, "0"}, {e, "(too bright) ≥ +" + scale}},
           "V − " + reference_v(s.reference) + " (signed)")
    << "<p class='note'>One scale for every method of this scene: " << scale
    << " (the median over the methods of their 99th-percentile error, rounded up; larger "
       "errors saturate). Grey: background. Light 0 only.</p></div>\n";
  return o.str();
}

std::string cell(double v, const char* format) {
  if (!std::isfinite(v)) return "<td data-v=''>–</td>";
  return "<td data-v='" + fmt("%.9g", v) + "'>" + fmt(format, v) + "</td>";
}

std::string metrics_table(const SceneEntry& s) {
  std::ostringstream o;
  o << "<table class='sortable'><thead><tr><th>method</th><th>time (ms)</th>"
       "<th>speed vs raytrace</th><th>rays in same time</th><th>mean abs (shadowed)</th><th>mean "
       "abs</th><th>max abs</th>"
       "<th>rmse</th><th>PSNR (dB)</th><th>&gt; 1/255</th><th>&gt; 1/16</th></tr></thead><tbody>\n";
  for (const MethodEntry& m : s.methods) {
    o << "<tr><td data-v='" << xml_escape(m.method) << "'>" << xml_escape(m.method) << "</td>";
    if (!m.failure.empty()) {
      o << "<td class='failed' colspan='10' data-v=''>failed: " << xml_escape(m.failure)
        << "</td></tr>\n";
      continue;
    }
    o << cell(m.ms, "%.1f") << cell(speed_vs_raytrace(s, m), "%.2f×")
      << cell(rays_in_same_time(s, m), "%.0f");
    if (m.vs_exact) {
      const ErrorStats& e = *m.vs_exact;
      o << cell(e.mean_abs_shadowed, "%.5f") << cell(e.mean_abs, "%.5f") << cell(e.max_abs, "%.4f")
        << cell(e.rmse, "%.5f") << cell(e.psnr >= kPsnrCap ? std::nan("") : e.psnr, "%.1f")
        << cell(e.frac_over_1_255, "%.4f") << cell(e.frac_over_1_16, "%.4f");
    } else {
      o << "<td data-v='-1' colspan='7' style='text-align:left'>reference</td>";
    }
    o << "</tr>\n";
  }
  o << "</tbody></table>\n";
  return o.str();
}

/// Markdown `**x**` and backquotes of the column key as HTML.
std::string key_html(const std::string& reference) {
  std::string md = table_column_key(reference), out = "<ul class='key'>";
  bool bold = false, code = false;
  for (size_t i = 0; i < md.size(); ++i) {
    if (md.compare(i, 2, "- ") == 0 && (i == 0 || md[i - 1] == '\n')) {
      out += "<li>";
      ++i;
    } else if (md.compare(i, 2, "**") == 0) {
      out += bold ? "</b>" : "<b>";
      bold = !bold;
      ++i;
    } else if (md[i] == '`') {
      out += code ? "</code>" : "<code>";
      code = !code;
    } else {
      out += xml_escape(std::string(1, md[i]));
    }
  }
  out +=
      "<li><b>PSNR</b> = 10 log10(1 / mse); <b>&gt; 1/16</b> = fraction of pixels off by more "
      "than 1/16. Click a column to sort.</ul>\n";
  return out;
}

std::string stage_chart(const SceneEntry& s) {
  std::vector<plot::Bar> bars;
  for (const MethodEntry& m : s.methods) {
    if (!m.failure.empty()) continue;
    plot::Bar b{m.method, m.stages};
    double staged = 0.0;
    for (const auto& [name, ms] : m.stages) staged += ms;
    if (m.ms - staged > 0.05 * m.ms) b.segments.emplace_back("(not in a stage)", m.ms - staged);
    bars.push_back(std::move(b));
  }
  return plot::stacked_bars_svg("Where each method's time goes (" + s.name + ")",
                                "milliseconds, all lights", bars, 760);
}

std::string frame_stages(const SceneEntry& s) {
  std::string out;
  for (const auto& [key, value] : s.frame.items()) {
    if (!value.is_number()) continue;
    out += (out.empty() ? "" : ", ") + key + " " + fmt("%.1f", value.get<double>());
  }
  return out.empty() ? "" : "Shared by every method (not in their times): " + out + ".";
}

std::string scene_section(const SceneEntry& s) {
  std::ostringstream o;
  o << "<section class='scene' id='scene-" << xml_escape(s.folder) << "'>\n<h2>"
    << xml_escape(s.name) << "</h2>\n<p class='meta'>" << xml_escape(s.summary_header)
    << "</p>\n<p class='meta'>" << xml_escape(frame_stages(s)) << "</p>\n";
  const std::string vr = reference_v(s.reference);
  o << "<h3>Beauty: the reference (" << xml_escape(s.reference) << ") and every method</h3>\n"
    << figure_grid(s, "", true, "beauty", false);
  o << "<h3>Error maps on one scale</h3>\n"
    << legends(s) << "<p class='note'>|V − " << vr << "|</p>"
    << figure_grid(s, "_abs", false, "absolute error", false) << "<p class='note'>V − " << vr
    << ": blue = the method's shadow is too dark, red = too "
       "bright</p>"
    << figure_grid(s, "_signed", false, "signed error", false);
  o << "<h3>Penumbra close-up</h3>\n<p class='note'>The " << s.crop.size << "×" << s.crop.size
    << " window at (" << s.crop.x << ", " << s.crop.y << ") with the most penumbra pixels, "
    << s.crop_zoom << "× enlarged (each pixel drawn " << s.crop_zoom << "×" << s.crop_zoom
    << " CSS pixels); beauty, then |V − " << vr << "| on the same scale.</p>"
    << figure_grid(s, "_crop", true, "penumbra crop", true)
    << figure_grid(s, "_crop_abs", false, "penumbra crop error", true);
  o << "<h3>Error and time</h3>\n" << metrics_table(s) << key_html(s.reference);
  o << "<h3>Stage breakdown</h3>\n<div class='charts'>" << stage_chart(s) << "</div>\n";
  o << "</section>\n";
  return o.str();
}

std::string error_vs_time(const ReportData& d) {
  std::vector<std::string> methods;
  for (const SceneEntry& s : d.scenes)
    for (const MethodEntry& m : s.methods)
      if (!is_reference(s, m) &&
          std::find(methods.begin(), methods.end(), m.method) == methods.end())
        methods.push_back(m.method);
  std::vector<plot::Series> series;
  for (const std::string& name : methods) {
    plot::Series ser;
    ser.name = name;
    ser.lines = false;
    for (size_t i = 0; i < d.scenes.size(); ++i) {
      const MethodEntry* m = d.scenes[i].find(name);
      if (!m || !m->vs_exact) continue;
      ser.x.push_back(m->ms);
      ser.y.push_back(std::max(m->vs_exact->mean_abs_shadowed, kErrorFloor));
      ser.marker.push_back(static_cast<int>(i));
      ser.tooltip.push_back(name + " on " + d.scenes[i].name + ": " + fmt("%.1f ms", m->ms) +
                            ", error " + fmt("%.5f", m->vs_exact->mean_abs_shadowed));
    }
    series.push_back(std::move(ser));
  }
  plot::Chart chart;
  chart.title = "Error against time: lower left is better";
  chart.x = {"method time (ms, log scale)", plot::Scale::log10};
  chart.y = {"mean |V − " + reference_v(d.reference) + "| over shadowed pixels (log scale)",
             plot::Scale::log10};
  chart.width = 860;
  chart.height = 480;
  for (const SceneEntry& s : d.scenes) chart.marker_names.push_back("scene " + s.name);
  return plot::line_plot_svg(chart, series);
}

std::string sweep_charts(const SweepEntry& sw, const std::string& reference) {
  std::vector<plot::Series> err, time;
  for (const SweepCurve& c : sw.curves) {
    err.push_back({c.method, sw.x, floored(c.error), false, true, {}, {}, ""});
    time.push_back({c.method, sw.x, c.ms, false, true, {}, {}, ""});
  }
  plot::Chart e;
  e.width = 600;
  e.title = "Error vs " + sw.name + " (" + sw.scene + ")";
  e.x = {sw.x_label, plot::Scale::log2};
  e.y = {"mean |V − " + reference_v(reference) + "| over shadowed pixels", plot::Scale::log10};
  plot::Chart t = e;
  t.title = "Time vs " + sw.name + " (" + sw.scene + ")";
  t.y = {"method time (ms)", plot::Scale::log10};
  return "<div class='charts'>" + plot::line_plot_svg(e, err) + plot::line_plot_svg(t, time) +
         "</div>\n";
}

}  // namespace

std::string error_vs_time_svg(const ReportData& data) {
  return error_vs_time(data);
}

std::string report_html(const ReportData& d) {
  std::ostringstream o;
  o << "<!DOCTYPE html>\n<html lang='en'><head><meta charset='utf-8'>\n"
    << "<meta name='viewport' content='width=device-width, initial-scale=1'>\n"
    << "<title>Penumbra report: ";
  for (size_t i = 0; i < d.scenes.size(); ++i) o << (i ? ", " : "") << xml_escape(d.scenes[i].name);
  o << "</title>\n<style>" << kStyle << "</style></head>\n<body>\n<header class='top'>\n"
    << "<h1>Penumbra: soft shadows against "
    << (d.reference == "exact" ? "the exact reference" : "the reference " + xml_escape(d.reference))
    << "</h1>\n<dl>"
    << "<dt>date</dt><dd>" << xml_escape(d.machine.date_utc) << "</dd>"
    << "<dt>machine</dt><dd>" << d.machine.cores << " hardware threads, "
    << xml_escape(d.machine.cpu) << "; load average " << xml_escape(d.machine.load)
    << " (times are wall-clock: compare ratios within a scene)</dd>"
    << "<dt>build</dt><dd>" << xml_escape(d.machine.build) << "</dd>"
    << "<dt>command</dt><dd><code>" << xml_escape(d.command_line) << "</code></dd>"
    << "<dt>light samples</dt><dd>" << xml_escape(d.samples) << "</dd>"
    << "<dt>reference</dt><dd>" << xml_escape(d.reference) << "</dd>"
    << "<dt>scenes</dt><dd>";
  for (size_t i = 0; i < d.scenes.size(); ++i)
    o << (i ? "; " : "") << xml_escape(d.scenes[i].name) << " " << d.scenes[i].width << "×"
      << d.scenes[i].height;
  o << "</dd></dl>\n</header>\n<nav>";
  for (const SceneEntry& s : d.scenes)
    o << "<a href='#scene-" << xml_escape(s.folder) << "'>" << xml_escape(s.name) << "</a>";
  o << "<a href='#across'>across scenes</a></nav>\n<main>\n";
  for (const SceneEntry& s : d.scenes) o << scene_section(s);
  o << "<section class='across' id='across'>\n<h2>Across scenes</h2>\n"
    << "<p class='note'>Each method is one colour, each scene one marker shape (hover a point "
       "for its numbers). Errors below 1e-6 (exact up to float rounding) are drawn at 1e-6.</p>\n"
    << "<div class='charts'>" << error_vs_time(d) << "</div>\n";
  for (const SweepEntry& sw : d.sweeps) {
    o << "<h3>Sweep: " << xml_escape(sw.name) << " on " << xml_escape(sw.scene) << "</h3>\n"
      << sweep_charts(sw, d.reference);
  }
  if (d.sweeps.empty())
    o << "<p class='note'>No sweeps in this report (add <code>--sweep samples --sweep "
         "light_size --sweep resolution</code>).</p>\n";
  o << "</section>\n</main>\n<script>" << kScript << "</script>\n</body></html>\n";
  return o.str();
}

nlohmann::json report_json(const ReportData& d) {
  nlohmann::json j;
  j["machine"] = {{"cpu", d.machine.cpu},
                  {"cores", d.machine.cores},
                  {"load", d.machine.load},
                  {"build", d.machine.build},
                  {"date", d.machine.date_utc}};
  j["command"] = d.command_line;
  j["samples"] = d.samples;
  j["reference"] = d.reference;
  j["scenes"] = nlohmann::json::array();
  for (const SceneEntry& s : d.scenes) {
    nlohmann::json js = {{"name", s.name},
                         {"folder", s.folder},
                         {"width", s.width},
                         {"height", s.height},
                         {"frame", s.frame},
                         {"error_scale", s.error_scale},
                         {"crop", {{"x", s.crop.x}, {"y", s.crop.y}, {"size", s.crop.size}}}};
    js["methods"] = nlohmann::json::array();
    for (const MethodEntry& m : s.methods) {
      nlohmann::json jm = m.failure.empty() ? m.stats : nlohmann::json{{"method", m.method}};
      if (!m.failure.empty()) jm["failure"] = m.failure;
      const double speed = speed_vs_raytrace(s, m);
      if (std::isfinite(speed)) jm["speed_vs_raytrace"] = speed;
      const double rays = rays_in_same_time(s, m);
      if (std::isfinite(rays)) jm["equal_time_rays"] = rays;
      js["methods"].push_back(jm);
    }
    j["scenes"].push_back(js);
  }
  j["sweeps"] = nlohmann::json::array();
  for (const SweepEntry& sw : d.sweeps) {
    nlohmann::json js = {
        {"name", sw.name}, {"scene", sw.scene}, {"x_label", sw.x_label}, {"x", sw.x}};
    for (const SweepCurve& c : sw.curves) {
      nlohmann::json err = nlohmann::json::array(), ms = nlohmann::json::array();
      for (size_t i = 0; i < c.error.size(); ++i) {
        err.push_back(std::isfinite(c.error[i]) ? nlohmann::json(c.error[i]) : nlohmann::json());
        ms.push_back(std::isfinite(c.ms[i]) ? nlohmann::json(c.ms[i]) : nlohmann::json());
      }
      js["methods"][c.method] = {{"mean_abs_shadowed", err}, {"time_ms", ms}};
    }
    j["sweeps"].push_back(js);
  }
  return j;
}

std::string report_markdown(const ReportData& d) {
  std::ostringstream o;
  o << "Generated by `" << d.command_line << "` on " << d.machine.date_utc << ".\n"
    << "Machine: " << d.machine.cores << " hardware threads, " << d.machine.cpu << "; load average "
    << d.machine.load << " (wall-clock times: compare ratios within a "
    << "table). Build: " << d.machine.build << ".\n";
  if (d.reference != "exact") o << "Errors against `" << d.reference << "`.\n";
  for (const SceneEntry& s : d.scenes) o << "\n### " << s.name << "\n\n" << s.results_md;
  return o.str();
}

}  // namespace penumbra::report
