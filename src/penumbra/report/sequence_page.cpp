#include "penumbra/report/sequence_page.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <string>
#include <vector>

#include "penumbra/report/svg_plot.hpp"

namespace penumbra {

namespace {

using nlohmann::json;
using plot::xml_escape;

/// Method names in the order frames.json lists them (the render's order).
std::vector<std::string> method_order(const json& doc) {
  std::vector<std::string> names;
  for (const json& e : doc.at("frames")) {
    const std::string name = e.at("method").get<std::string>();
    if (std::find(names.begin(), names.end(), name) == names.end()) names.push_back(name);
  }
  return names;
}

double value_of(const json& object, const char* key) {
  const auto it = object.find(key);
  return it != object.end() && it->is_number() ? it->get<double>() : std::nan("");
}

/// One series per method of `value(entry)` against the frame index.
template <class Value>
std::vector<plot::Series> per_frame(const json& doc, const std::vector<std::string>& names,
                                    Value&& value) {
  std::vector<plot::Series> series(names.size());
  for (size_t m = 0; m < names.size(); ++m) series[m].name = names[m];
  for (const json& e : doc.at("frames")) {
    const auto m = std::find(names.begin(), names.end(), e.at("method").get<std::string>());
    plot::Series& s = series[static_cast<size_t>(m - names.begin())];
    s.x.push_back(e.at("frame").get<double>());
    s.y.push_back(value(e));
  }
  std::erase_if(series, [](const plot::Series& s) {
    return std::none_of(s.y.begin(), s.y.end(), [](double y) { return std::isfinite(y); });
  });
  return series;
}

std::string number(double v, const char* format) {
  if (!std::isfinite(v)) return "–";
  char text[48];
  std::snprintf(text, sizeof text, format, v);
  return text;
}

std::string summary_table(const json& doc, const std::vector<std::string>& names) {
  std::string html =
      "<table><tr><th>method</th><th>frames</th><th>mean ms / frame</th><th>mean |ΔV| vs "
      "exact</th><th>max |ΔV| vs exact</th><th>temporal error</th></tr>\n";
  for (const std::string& name : names) {
    const json& s = doc.at("summary").at(name);
    const json none = json::object();
    const json& err = s.contains("mean_error_vs_exact") ? s["mean_error_vs_exact"] : none;
    html += "<tr><td>" + xml_escape(name) + "</td><td>" + number(value_of(s, "frames"), "%.0f") +
            "</td><td>" + number(value_of(s, "mean_ms"), "%.1f") + "</td><td>" +
            number(value_of(err, "mean_abs"), "%.3e") + "</td><td>" +
            number(value_of(err, "max_abs"), "%.3e") + "</td><td>" +
            number(value_of(s, "mean_temporal_error"), "%.3e") + "</td></tr>\n";
  }
  return html + "</table>\n";
}

std::string plots(const json& doc, const std::vector<std::string>& names) {
  plot::Chart chart;
  chart.x.label = "frame";
  chart.width = 560;
  chart.height = 320;
  std::string html;
  chart.title = "time per frame";
  chart.y.label = "ms";
  html += plot::line_plot_svg(
      chart, per_frame(doc, names, [](const json& e) { return value_of(e, "total_ms"); }));
  chart.title = "error against exact";
  chart.y.label = "mean |ΔV|";
  const auto error = per_frame(doc, names, [](const json& e) {
    return e.contains("error_vs_exact") ? value_of(e["error_vs_exact"], "mean_abs") : std::nan("");
  });
  if (!error.empty()) html += plot::line_plot_svg(chart, error);
  chart.title = "temporal error (flicker the reference has not)";
  chart.y.label = "mean |ΔV − ΔV_exact|";
  const auto temporal =
      per_frame(doc, names, [](const json& e) { return value_of(e, "temporal_error"); });
  if (!temporal.empty()) html += plot::line_plot_svg(chart, temporal);
  return "<div class=plots>" + html + "</div>\n";
}

std::string frame_folder(int index) {
  char name[32];
  std::snprintf(name, sizeof name, "frame_%04d", index);
  return name;
}

/// Videos, or a flip-book: every method's beauty images shown in turn at the sequence's fps.
std::string playback(const json& doc, const std::vector<std::string>& names, bool videos) {
  std::string html = "<h2>The sequence</h2>\n<div class=play>\n";
  if (videos) {
    html +=
        "<figure><video src=\"compare.mp4\" controls loop muted autoplay></video>"
        "<figcaption>all methods side by side</figcaption></figure>\n";
    for (const std::string& name : names)
      html += "<figure><video src=\"" + xml_escape(name) +
              "/beauty.mp4\" controls loop muted></video><figcaption>" + xml_escape(name) +
              "</figcaption></figure>\n";
    return html + "</div>\n";
  }
  std::vector<int> frames;
  for (const json& e : doc.at("frames")) {
    const int f = e.at("frame").get<int>();
    if (frames.empty() || frames.back() != f) frames.push_back(f);
  }
  std::string list;
  for (int f : frames) list += (list.empty() ? "\"" : ",\"") + frame_folder(f) + "\"";
  for (const std::string& name : names)
    html += "<figure><img class=flip data-method=\"" + xml_escape(name) + "\" src=\"" +
            xml_escape(name) + "/" + frame_folder(frames.front()) + "/beauty.png\"><figcaption>" +
            xml_escape(name) + "</figcaption></figure>\n";
  const double fps = value_of(doc, "fps");
  html +=
      "</div>\n<p>A flip-book of the frames' beauty images (ffmpeg was not found, so no "
      "videos). <button id=toggle>pause</button> <span id=frame></span></p>\n"
      "<script>\nconst frames = [" +
      list +
      "];\nlet i = 0, playing = true;\nfunction show() {\n"
      "  for (const img of document.querySelectorAll('img.flip'))\n"
      "    img.src = img.dataset.method + '/' + frames[i] + '/beauty.png';\n"
      "  document.getElementById('frame').textContent = frames[i];\n}\n"
      "setInterval(() => { if (playing) { i = (i + 1) % frames.length; show(); } }, " +
      number(1000.0 / (std::isfinite(fps) && fps > 0.0 ? fps : 24.0), "%.0f") +
      ");\ndocument.getElementById('toggle').onclick = (e) => {\n"
      "  playing = !playing; e.target.textContent = playing ? 'pause' : 'play';\n};\n"
      "show();\n</script>\n";
  return html;
}

}  // namespace

std::string sequence_page_html(const json& doc, bool videos) {
  const std::vector<std::string> names = method_order(doc);
  const std::string scene = doc.value("scene", std::string("scene"));
  const json& range = doc.at("range");
  const json& moves = doc.at("moves");
  std::string what;
  for (const char* k : {"geometry", "lights", "camera"})
    if (moves.value(k, false)) what += (what.empty() ? "" : ", ") + std::string(k);
  std::string html =
      "<!doctype html>\n<html lang=en><head><meta charset=utf-8><title>" + xml_escape(scene) +
      " — sequence</title>\n<style>body{font:14px sans-serif;margin:2em;max-width:1300px}"
      "table{border-collapse:collapse}td,th{border:1px solid #ccc;padding:3px 8px;"
      "text-align:right}td:first-child,th:first-child{text-align:left}.plots,.play{display:"
      "flex;flex-wrap:wrap;gap:12px}figure{margin:0}video,img{max-width:420px}</style></head>"
      "<body>\n<h1>" +
      xml_escape(scene) + ": frames " + std::to_string(range.value("first", 0)) + "–" +
      std::to_string(range.value("last", 0)) + " (step " + std::to_string(range.value("step", 1)) +
      ") at " + number(value_of(doc, "fps"), "%g") +
      " fps</h1>\n<p>Moving: " + (what.empty() ? std::string("nothing") : what) +
      ". Times are each method's own per frame (what it redoes when the geometry moves "
      "included); errors are against <code>exact</code> on the same frame; the temporal error "
      "is the mean |(V<sub>t</sub> − V<sub>t−1</sub>) − (E<sub>t</sub> − E<sub>t−1</sub>)| over "
      "the surface pixels: flicker and popping the reference has not. The numbers: "
      "<a href=\"frames.json\">frames.json</a>, <a href=\"frames.csv\">frames.csv</a>.</p>\n" +
      summary_table(doc, names) + plots(doc, names) + playback(doc, names, videos) +
      "</body></html>\n";
  return html;
}

}  // namespace penumbra
