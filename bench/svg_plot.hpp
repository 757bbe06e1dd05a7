// A tiny SVG line-plot writer for the sweep programs: one chart, linear or log2 x axis, linear y
// axis from 0, ticks, grid, axis labels and a legend. No dependencies.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace penumbra::bench {

struct PlotSeries {
  std::string name;
  std::vector<double> x;
  std::vector<double> y;
  bool dashed = false;
};

struct PlotSpec {
  std::string title;
  std::string x_label;
  std::string y_label;
  bool log2_x = false;  // x ticks at the data's powers of two
};

/// Writes `series` as an SVG line plot to `path` (throws std::runtime_error if it cannot).
inline void write_svg_plot(const std::string& path, const PlotSpec& spec,
                           const std::vector<PlotSeries>& series) {
  const double W = 640, H = 400, left = 72, right = 170, top = 40, bottom = 56;
  const double pw = W - left - right, ph = H - top - bottom;
  auto tx = [&](double x) { return spec.log2_x ? std::log2(x) : x; };
  double x0 = 1e300, x1 = -1e300, y1 = 0.0;
  for (const PlotSeries& s : series) {
    for (double x : s.x) x0 = std::min(x0, tx(x)), x1 = std::max(x1, tx(x));
    for (double y : s.y) y1 = std::max(y1, y);
  }
  if (!(x1 > x0)) x1 = x0 + 1.0;
  // A "nice" y step: 1, 2 or 5 × 10^k, about 5 ticks.
  if (!(y1 > 0.0)) y1 = 1.0;
  const double raw = y1 / 5.0, mag = std::pow(10.0, std::floor(std::log10(raw)));
  const double step = raw / mag <= 1   ? mag
                      : raw / mag <= 2 ? 2 * mag
                      : raw / mag <= 5 ? 5 * mag
                                       : 10 * mag;
  y1 = std::ceil(y1 / step - 1e-9) * step;
  auto px = [&](double x) { return left + (tx(x) - x0) / (x1 - x0) * pw; };
  auto py = [&](double y) { return top + ph - y / y1 * ph; };
  auto num = [](double v) {
    char b[32];
    std::snprintf(b, sizeof b, "%g", v);
    return std::string(b);
  };
  static const char* colors[] = {"#1f77b4", "#d62728", "#2ca02c", "#ff7f0e",
                                 "#9467bd", "#8c564b", "#e377c2", "#17becf"};

  std::ostringstream o;
  o << "<svg xmlns='http://www.w3.org/2000/svg' width='" << W << "' height='" << H
    << "' font-family='sans-serif' font-size='12'>\n"
    << "<rect width='100%' height='100%' fill='white'/>\n"
    << "<text x='" << left + pw / 2 << "' y='22' text-anchor='middle' font-size='14'>" << spec.title
    << "</text>\n";
  // Y ticks and grid.
  for (double y = 0.0; y <= y1 + 1e-12 * y1; y += step) {
    o << "<line x1='" << left << "' x2='" << left + pw << "' y1='" << py(y) << "' y2='" << py(y)
      << "' stroke='#ddd'/>\n"
      << "<text x='" << left - 6 << "' y='" << py(y) + 4 << "' text-anchor='end'>" << num(y)
      << "</text>\n";
  }
  // X ticks at the distinct x values of the data (sweeps have few).
  std::vector<double> xs;
  for (const PlotSeries& s : series) xs.insert(xs.end(), s.x.begin(), s.x.end());
  std::sort(xs.begin(), xs.end());
  xs.erase(std::unique(xs.begin(), xs.end()), xs.end());
  for (double x : xs) {
    o << "<line x1='" << px(x) << "' x2='" << px(x) << "' y1='" << top + ph << "' y2='"
      << top + ph + 5 << "' stroke='black'/>\n"
      << "<text x='" << px(x) << "' y='" << top + ph + 18 << "' text-anchor='middle'>" << num(x)
      << "</text>\n";
  }
  o << "<rect x='" << left << "' y='" << top << "' width='" << pw << "' height='" << ph
    << "' fill='none' stroke='black'/>\n"
    << "<text x='" << left + pw / 2 << "' y='" << H - 14 << "' text-anchor='middle'>"
    << spec.x_label << "</text>\n"
    << "<text transform='translate(18," << top + ph / 2 << ") rotate(-90)' text-anchor='middle'>"
    << spec.y_label << "</text>\n";
  // Lines, markers, legend.
  for (size_t i = 0; i < series.size(); ++i) {
    const PlotSeries& s = series[i];
    const char* c = colors[i % 8];
    o << "<polyline fill='none' stroke='" << c << "' stroke-width='2'"
      << (s.dashed ? " stroke-dasharray='6,4'" : "") << " points='";
    for (size_t k = 0; k < s.x.size() && k < s.y.size(); ++k)
      o << px(s.x[k]) << "," << py(s.y[k]) << " ";
    o << "'/>\n";
    for (size_t k = 0; k < s.x.size() && k < s.y.size(); ++k)
      o << "<circle cx='" << px(s.x[k]) << "' cy='" << py(s.y[k]) << "' r='3' fill='" << c
        << "'/>\n";
    const double ly = top + 10 + 20 * static_cast<double>(i), lx = left + pw + 12;
    o << "<line x1='" << lx << "' x2='" << lx + 24 << "' y1='" << ly << "' y2='" << ly
      << "' stroke='" << c << "' stroke-width='2'" << (s.dashed ? " stroke-dasharray='6,4'" : "")
      << "/>\n<text x='" << lx + 30 << "' y='" << ly + 4 << "'>" << s.name << "</text>\n";
  }
  o << "</svg>\n";
  std::ofstream f(path);
  if (!f) throw std::runtime_error("cannot write " + path);
  f << o.str();
}

}  // namespace penumbra::bench
