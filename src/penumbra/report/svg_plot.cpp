#include "penumbra/report/svg_plot.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <limits>
#include <map>
#include <sstream>

#include "penumbra/core/error.hpp"
#include "penumbra/core/files.hpp"

namespace penumbra::plot {

namespace {

constexpr const char* kPalette[] = {"#4e79a7", "#e15759", "#59a14f", "#f28e2b", "#b07aa1",
                                    "#76b7b2", "#edc948", "#9c755f", "#ff9da7", "#bab0ac"};

std::string num(double v) {
  char b[32];
  std::snprintf(b, sizeof b, "%.2f", v);
  return b;
}

bool usable(double v, Scale s) {
  return std::isfinite(v) && (s == Scale::linear || v > 0.0);
}

double transform(double v, Scale s) {
  switch (s) {
    case Scale::linear:
      return v;
    case Scale::log2:
      return std::log2(v);
    case Scale::log10:
      return std::log10(v);
  }
  return v;
}

/// 1, 2 or 5 × 10^k, about `count` steps over `span`.
double nice_step(double span, int count) {
  const double raw = span / count, mag = std::pow(10.0, std::floor(std::log10(raw)));
  const double r = raw / mag;
  return (r <= 1 ? 1 : r <= 2 ? 2 : r <= 5 ? 5 : 10) * mag;
}

/// An axis mapped onto [0, 1]: its transformed range and its ticks (value, label).
struct AxisLayout {
  double lo = 0.0, hi = 1.0;  // transformed
  std::vector<std::pair<double, std::string>> ticks;
  Scale scale = Scale::linear;

  double unit(double v) const { return (transform(v, scale) - lo) / (hi - lo); }
};

AxisLayout layout_axis(const std::vector<double>& values, Scale scale, bool from_zero) {
  AxisLayout a;
  a.scale = scale;
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  for (double v : values)
    if (usable(v, scale)) lo = std::min(lo, v), hi = std::max(hi, v);
  if (!std::isfinite(lo)) lo = scale == Scale::linear ? 0.0 : 1.0, hi = lo + 1.0;
  if (scale == Scale::linear) {
    if (from_zero) lo = std::min(lo, 0.0);
    if (!(hi > lo)) hi = lo + (lo == 0.0 ? 1.0 : std::fabs(lo));
    const double step = nice_step(hi - lo, 5);
    lo = std::floor(lo / step + 1e-9) * step;
    hi = std::ceil(hi / step - 1e-9) * step;
    for (double v = lo; v <= hi + 1e-9 * step; v += step)
      a.ticks.emplace_back(v, tick_label(std::fabs(v) < 1e-12 * step ? 0.0 : v));
    a.lo = lo;
    a.hi = hi;
  } else if (scale == Scale::log2) {
    std::vector<double> xs;
    for (double v : values)
      if (usable(v, scale)) xs.push_back(v);
    std::sort(xs.begin(), xs.end());
    xs.erase(std::unique(xs.begin(), xs.end()), xs.end());
    for (double v : xs) a.ticks.emplace_back(v, tick_label(v));
    a.lo = std::log2(lo);
    a.hi = std::log2(hi);
    if (!(a.hi > a.lo)) a.lo -= 0.5, a.hi += 0.5;
    const double pad = 0.04 * (a.hi - a.lo);
    a.lo -= pad;
    a.hi += pad;
  } else {
    a.lo = std::floor(std::log10(lo));
    a.hi = std::ceil(std::log10(hi));
    if (!(a.hi > a.lo)) a.hi = a.lo + 1.0;
    const bool short_range = a.hi - a.lo <= 2.0;
    for (int e = static_cast<int>(a.lo); e <= static_cast<int>(a.hi); ++e) {
      const double d = std::pow(10.0, e);
      a.ticks.emplace_back(d, tick_label(d));
      if (short_range && e < static_cast<int>(a.hi)) {
        a.ticks.emplace_back(2 * d, tick_label(2 * d));
        a.ticks.emplace_back(5 * d, tick_label(5 * d));
      }
    }
  }
  return a;
}

/// Marker shape `shape` centred at (x, y), radius r.
void marker(std::ostringstream& o, int shape, double x, double y, double r, const std::string& c,
            const std::string& title) {
  const std::string t = title.empty() ? "" : "<title>" + xml_escape(title) + "</title>";
  switch (((shape % 5) + 5) % 5) {
    case 0:
      o << "<circle cx='" << num(x) << "' cy='" << num(y) << "' r='" << num(r) << "' fill='" << c
        << "'>" << t << "</circle>\n";
      break;
    case 1:
      o << "<rect x='" << num(x - r) << "' y='" << num(y - r) << "' width='" << num(2 * r)
        << "' height='" << num(2 * r) << "' fill='" << c << "'>" << t << "</rect>\n";
      break;
    case 2:
      o << "<polygon points='" << num(x) << "," << num(y - 1.2 * r) << " " << num(x + 1.1 * r)
        << "," << num(y + 0.8 * r) << " " << num(x - 1.1 * r) << "," << num(y + 0.8 * r)
        << "' fill='" << c << "'>" << t << "</polygon>\n";
      break;
    case 3:
      o << "<polygon points='" << num(x) << "," << num(y - 1.3 * r) << " " << num(x + 1.3 * r)
        << "," << num(y) << " " << num(x) << "," << num(y + 1.3 * r) << " " << num(x - 1.3 * r)
        << "," << num(y) << "' fill='" << c << "'>" << t << "</polygon>\n";
      break;
    default:
      o << "<circle cx='" << num(x) << "' cy='" << num(y) << "' r='" << num(r)
        << "' fill='white' stroke='" << c << "' stroke-width='2'>" << t << "</circle>\n";
      break;
  }
}

std::string svg_open(double w, double h) {
  std::ostringstream o;
  o << "<svg xmlns='http://www.w3.org/2000/svg' width='" << w << "' height='" << h
    << "' viewBox='0 0 " << w << " " << h
    << "' font-family='system-ui, sans-serif' font-size='12' role='img'>\n"
    << "<rect width='100%' height='100%' fill='white'/>\n";
  return o.str();
}

}  // namespace

const char* palette_color(size_t index) {
  return kPalette[index % std::size(kPalette)];
}

std::string distinct_color(size_t index, size_t count) {
  if (count <= std::size(kPalette)) return palette_color(index);
  // ceil(count / 3) hues evenly spaced around the wheel, each at three lightness levels: colours
  // of one level differ in hue by at least 360° / hues, those of one hue in lightness.
  const size_t hues = (count + 2) / 3;
  const double hue = 6.0 * static_cast<double>(index % hues) / static_cast<double>(hues);
  const double lightness = std::array<double, 3>{0.47, 0.68, 0.30}[(index / hues) % 3];
  const double saturation = 0.75;
  const double chroma = (1.0 - std::fabs(2.0 * lightness - 1.0)) * saturation;
  const double x = chroma * (1.0 - std::fabs(std::fmod(hue, 2.0) - 1.0));
  const double m = lightness - 0.5 * chroma;
  double rgb[3] = {0.0, 0.0, 0.0};
  const int sector = static_cast<int>(hue) % 6;
  const int order[6][3] = {{0, 1, 2}, {1, 0, 2}, {1, 2, 0}, {2, 1, 0}, {2, 0, 1}, {0, 2, 1}};
  // sector k: the channel order[k][0] gets the chroma, order[k][1] x, order[k][2] nothing.
  rgb[order[sector][0]] = chroma;
  rgb[order[sector][1]] = x;
  char hex[8];
  std::snprintf(hex, sizeof hex, "#%02x%02x%02x", static_cast<int>(std::lround((rgb[0] + m) * 255)),
                static_cast<int>(std::lround((rgb[1] + m) * 255)),
                static_cast<int>(std::lround((rgb[2] + m) * 255)));
  return hex;
}

std::string tick_label(double value) {
  if (value == 0.0) return "0";
  char b[32];
  int digits = 1;
  for (; digits <= 6; ++digits) {
    std::snprintf(b, sizeof b, "%.*g", digits, value);
    if (std::fabs(std::strtod(b, nullptr) - value) <= 0.005 * std::fabs(value)) break;
  }
  const double mag = std::fabs(value);
  if (std::strchr(b, 'e') && mag >= 1e-4 && mag < 1e6) {  // 150, not 1.5e+02
    const int decimals = std::max(0, digits - 1 - static_cast<int>(std::floor(std::log10(mag))));
    std::snprintf(b, sizeof b, "%.*f", decimals, value);
  }
  return b;
}

std::string xml_escape(const std::string& text) {
  std::string out;
  out.reserve(text.size());
  for (char c : text) {
    switch (c) {
      case '&':
        out += "&amp;";
        break;
      case '<':
        out += "&lt;";
        break;
      case '>':
        out += "&gt;";
        break;
      case '\'':
        out += "&#39;";
        break;
      case '"':
        out += "&quot;";
        break;
      default:
        out += c;
    }
  }
  return out;
}

void write_text_file(const std::filesystem::path& path, const std::string& text) {
  penumbra::write_text_file(path, text);  // atomic: never a truncated file under its name
}

std::string line_plot_svg(const Chart& chart, const std::vector<Series>& series) {
  const double W = chart.width, H = chart.height, left = 70, top = 36, bottom = 52;
  double legend_w = 0;
  for (const Series& s : series)
    legend_w = std::max(legend_w, 40.0 + 7.0 * static_cast<double>(s.name.size()));
  for (const std::string& m : chart.marker_names)
    legend_w = std::max(legend_w, 30.0 + 7.0 * static_cast<double>(m.size()));
  const double right = std::min(220.0, legend_w + 16);
  const double pw = W - left - right, ph = H - top - bottom;

  std::vector<double> xs, ys;
  for (const Series& s : series) {
    for (size_t k = 0; k < s.x.size() && k < s.y.size(); ++k) {
      if (!usable(s.x[k], chart.x.scale) || !usable(s.y[k], chart.y.scale)) continue;
      xs.push_back(s.x[k]);
      ys.push_back(s.y[k]);
    }
  }
  const AxisLayout ax = layout_axis(xs, chart.x.scale, false);
  const AxisLayout ay = layout_axis(ys, chart.y.scale, true);
  const auto px = [&](double x) { return left + ax.unit(x) * pw; };
  const auto py = [&](double y) { return top + ph - ay.unit(y) * ph; };

  std::ostringstream o;
  o << svg_open(W, H);
  o << "<text x='" << num(left + pw / 2) << "' y='20' text-anchor='middle' font-size='14' "
    << "font-weight='600'>" << xml_escape(chart.title) << "</text>\n";
  for (const auto& [v, label] : ay.ticks) {
    const double y = py(v);
    o << "<line x1='" << num(left) << "' x2='" << num(left + pw) << "' y1='" << num(y) << "' y2='"
      << num(y) << "' stroke='#e3e3e3'/>\n<text x='" << num(left - 6) << "' y='" << num(y + 4)
      << "' text-anchor='end'>" << xml_escape(label) << "</text>\n";
  }
  for (const auto& [v, label] : ax.ticks) {
    const double x = px(v);
    o << "<line x1='" << num(x) << "' x2='" << num(x) << "' y1='" << num(top) << "' y2='"
      << num(top + ph) << "' stroke='#f0f0f0'/>\n<line x1='" << num(x) << "' x2='" << num(x)
      << "' y1='" << num(top + ph) << "' y2='" << num(top + ph + 5) << "' stroke='#333'/>\n"
      << "<text x='" << num(x) << "' y='" << num(top + ph + 18) << "' text-anchor='middle'>"
      << xml_escape(label) << "</text>\n";
  }
  o << "<rect x='" << num(left) << "' y='" << num(top) << "' width='" << num(pw) << "' height='"
    << num(ph) << "' fill='none' stroke='#333'/>\n"
    << "<text x='" << num(left + pw / 2) << "' y='" << num(H - 12) << "' text-anchor='middle'>"
    << xml_escape(chart.x.label) << "</text>\n"
    << "<text transform='translate(16," << num(top + ph / 2)
    << ") rotate(-90)' text-anchor='middle'>" << xml_escape(chart.y.label) << "</text>\n";

  double ly = top + 8;
  const double lx = left + pw + 14;
  struct Point {
    int shape;
    double x, y, r;
    std::string colour, title;
  };
  std::vector<Point> points;  // every marker, drawn after the lines
  for (size_t i = 0; i < series.size(); ++i) {
    const Series& s = series[i];
    const std::string c = s.color.empty() ? distinct_color(i, series.size()) : s.color;
    if (s.lines) {
      o << "<polyline fill='none' stroke='" << c << "' stroke-width='2'"
        << (s.dashed ? " stroke-dasharray='6,4'" : "") << " points='";
      for (size_t k = 0; k < s.x.size() && k < s.y.size(); ++k)
        if (usable(s.x[k], chart.x.scale) && usable(s.y[k], chart.y.scale))
          o << num(px(s.x[k])) << "," << num(py(s.y[k])) << " ";
      o << "'/>\n";
    }
    for (size_t k = 0; k < s.x.size() && k < s.y.size(); ++k) {
      if (!usable(s.x[k], chart.x.scale) || !usable(s.y[k], chart.y.scale)) continue;
      const std::string title =
          k < s.tooltip.size() ? s.tooltip[k]
                               : s.name + ": " + tick_label(s.x[k]) + ", " + tick_label(s.y[k]);
      points.push_back({k < s.marker.size() ? s.marker[k] : 0, px(s.x[k]), py(s.y[k]),
                        s.lines ? 3.0 : 4.5, c, title});
    }
    if (s.lines) {
      o << "<line x1='" << num(lx) << "' x2='" << num(lx + 22) << "' y1='" << num(ly) << "' y2='"
        << num(ly) << "' stroke='" << c << "' stroke-width='2'"
        << (s.dashed ? " stroke-dasharray='6,4'" : "") << "/>\n";
    } else {
      marker(o, 0, lx + 11, ly, 4.5, c, "");
    }
    o << "<text x='" << num(lx + 28) << "' y='" << num(ly + 4) << "'>" << xml_escape(s.name)
      << "</text>\n";
    ly += 18;
  }
  // Markers that fall on an earlier one (two methods with the same time and error: same scene,
  // same shape) would hide it exactly: the n-th on a spot is drawn larger by n steps, and the
  // larger ones first, so that each shows as a ring around the next.
  for (size_t i = 0; i < points.size(); ++i) {
    int below = 0;
    for (size_t j = 0; j < i; ++j)
      below += std::hypot(points[i].x - points[j].x, points[i].y - points[j].y) < 0.6 * points[j].r
                   ? 1
                   : 0;
    points[i].r *= 1.0 + 0.45 * below;
  }
  std::stable_sort(points.begin(), points.end(),
                   [](const Point& a, const Point& b) { return a.r > b.r; });
  for (const Point& p : points) marker(o, p.shape, p.x, p.y, p.r, p.colour, p.title);
  if (!chart.marker_names.empty()) ly += 8;
  for (size_t m = 0; m < chart.marker_names.size(); ++m) {
    marker(o, static_cast<int>(m), lx + 11, ly, 4.5, "#555", "");
    o << "<text x='" << num(lx + 28) << "' y='" << num(ly + 4) << "'>"
      << xml_escape(chart.marker_names[m]) << "</text>\n";
    ly += 18;
  }
  o << "</svg>\n";
  return o.str();
}

std::string stacked_bars_svg(const std::string& title, const std::string& value_label,
                             const std::vector<Bar>& bars, int width) {
  std::vector<std::string> names;  // segment names in first-seen order
  double max_total = 0.0;
  size_t label_chars = 4;
  for (const Bar& b : bars) {
    double total = 0.0;
    for (const auto& [name, v] : b.segments) {
      if (std::find(names.begin(), names.end(), name) == names.end()) names.push_back(name);
      total += std::max(v, 0.0);
    }
    max_total = std::max(max_total, total);
    label_chars = std::max(label_chars, b.label.size());
  }
  if (!(max_total > 0.0)) max_total = 1.0;
  const double bar_h = 18, gap = 6, top = 34;
  const double left = 14 + 7.0 * static_cast<double>(label_chars), right = 70;
  const int legend_cols = std::max(1, static_cast<int>((width - 20) / 170));
  const double legend_rows = std::ceil(static_cast<double>(names.size()) / legend_cols);
  const double plot_h = static_cast<double>(bars.size()) * (bar_h + gap);
  const double H = top + plot_h + 40 + legend_rows * 18 + 8;
  const double pw = width - left - right;
  const double step = nice_step(max_total, 5);
  const double axis_max = std::ceil(max_total / step - 1e-9) * step;
  const auto px = [&](double v) { return left + v / axis_max * pw; };
  std::map<std::string, std::string> color;
  for (size_t i = 0; i < names.size(); ++i) color[names[i]] = distinct_color(i, names.size());

  std::ostringstream o;
  o << svg_open(width, H);
  o << "<text x='" << num(width / 2.0) << "' y='20' text-anchor='middle' font-size='14' "
    << "font-weight='600'>" << xml_escape(title) << "</text>\n";
  for (double v = 0.0; v <= axis_max + 1e-9 * step; v += step) {
    o << "<line x1='" << num(px(v)) << "' x2='" << num(px(v)) << "' y1='" << num(top - 4)
      << "' y2='" << num(top + plot_h) << "' stroke='#e3e3e3'/>\n<text x='" << num(px(v)) << "' y='"
      << num(top + plot_h + 14) << "' text-anchor='middle'>" << tick_label(v) << "</text>\n";
  }
  o << "<text x='" << num(left + pw / 2) << "' y='" << num(top + plot_h + 30)
    << "' text-anchor='middle'>" << xml_escape(value_label) << "</text>\n";
  for (size_t b = 0; b < bars.size(); ++b) {
    const double y = top + static_cast<double>(b) * (bar_h + gap);
    o << "<text x='" << num(left - 6) << "' y='" << num(y + bar_h - 5) << "' text-anchor='end'>"
      << xml_escape(bars[b].label) << "</text>\n";
    double x = 0.0, total = 0.0;
    for (const auto& [name, v] : bars[b].segments) {
      const double w = std::max(v, 0.0);
      o << "<rect x='" << num(px(x)) << "' y='" << num(y) << "' width='" << num(px(x + w) - px(x))
        << "' height='" << bar_h << "' fill='" << color[name] << "'><title>"
        << xml_escape(bars[b].label + " / " + name + ": " + tick_label(v)) << "</title></rect>\n";
      x += w;
      total += w;
    }
    o << "<text x='" << num(px(x) + 4) << "' y='" << num(y + bar_h - 5) << "' fill='#333'>"
      << tick_label(total) << "</text>\n";
  }
  const double ly0 = top + plot_h + 44;
  for (size_t i = 0; i < names.size(); ++i) {
    const double lx = 10 + 170.0 * static_cast<double>(i % legend_cols);
    const double ly = ly0 + 18.0 * static_cast<double>(i / legend_cols);
    o << "<rect x='" << num(lx) << "' y='" << num(ly - 10) << "' width='12' height='12' fill='"
      << color[names[i]] << "'/>\n<text x='" << num(lx + 17) << "' y='" << num(ly) << "'>"
      << xml_escape(names[i]) << "</text>\n";
  }
  o << "</svg>\n";
  return o.str();
}

std::string color_bar_svg(const std::vector<std::string>& colors, double lo, double hi,
                          const std::vector<std::pair<double, std::string>>& ticks,
                          const std::string& caption, int width) {
  const double left = 14, right = 14, bar_h = 14, top = 22;
  const double bw = width - left - right;
  std::ostringstream o;
  o << svg_open(width, 60);
  o << "<defs><linearGradient id='g" << std::hash<std::string>{}(caption) % 100000 << "'>";
  for (size_t i = 0; i < colors.size(); ++i)
    o << "<stop offset='" << num(100.0 * static_cast<double>(i) / (colors.size() - 1))
      << "%' stop-color='" << colors[i] << "'/>";
  o << "</linearGradient></defs>\n";
  o << "<text x='" << num(left) << "' y='14'>" << xml_escape(caption) << "</text>\n";
  o << "<rect x='" << num(left) << "' y='" << top << "' width='" << num(bw) << "' height='" << bar_h
    << "' fill='url(#g" << std::hash<std::string>{}(caption) % 100000 << ")' stroke='#333'/>\n";
  for (const auto& [v, label] : ticks) {
    const double t = (v - lo) / (hi - lo), x = left + t * bw;
    // End labels align with the bar's ends so they stay inside the picture.
    const char* anchor = t < 0.01 ? "start" : t > 0.99 ? "end" : "middle";
    o << "<line x1='" << num(x) << "' x2='" << num(x) << "' y1='" << top + bar_h << "' y2='"
      << top + bar_h + 4 << "' stroke='#333'/>\n<text x='" << num(x) << "' y='" << top + bar_h + 17
      << "' text-anchor='" << anchor << "'>" << xml_escape(label) << "</text>\n";
  }
  o << "</svg>\n";
  return o.str();
}

}  // namespace penumbra::plot
