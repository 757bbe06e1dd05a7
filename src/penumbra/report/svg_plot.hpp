// Penumbra's one plotting module: small, dependency-free SVG charts for the comparison report
// and the sweep programs — line/scatter plots on linear, log2 or log10 axes, stacked horizontal
// bars, and colour-bar legends. Each chart is a standalone <svg> string, so it can be inlined in
// an HTML page (no script, no network) or written as a .svg file.
#pragma once

#include <filesystem>
#include <string>
#include <utility>
#include <vector>

namespace penumbra::plot {

enum class Scale {
  linear,  // y: from 0 (or the data's minimum if negative) with 1-2-5 ticks
  log2,    // ticks at the data's distinct values (sweeps over powers of two)
  log10,   // ticks at decades (and 2, 5 × 10^k when the range is short)
};

struct Axis {
  std::string label;
  Scale scale = Scale::linear;
};

struct Series {
  std::string name;
  std::vector<double> x;
  std::vector<double> y;
  bool dashed = false;
  bool lines = true;                 // false: markers only (scatter)
  std::vector<int> marker;           // per point: marker shape index (empty: circles)
  std::vector<std::string> tooltip;  // per point: <title> text (empty: "name: x, y")
  std::string color;                 // empty: distinct_color(series index, series count)
};

struct Chart {
  std::string title;
  Axis x, y;
  int width = 640;
  int height = 400;
  /// Names of the marker shapes used by Series::marker, shown as a second legend.
  std::vector<std::string> marker_names;
};

/// The palette (Tableau 10), cycling.
const char* palette_color(size_t index);

/// Colour `index` of `count` colours that must all differ: the palette for up to 10, beyond it
/// count / 3 evenly spaced hues at three lightness levels ("#rrggbb").
std::string distinct_color(size_t index, size_t count);

/// A line or scatter plot. Points with a non-finite value, or <= 0 on a log axis, are skipped.
std::string line_plot_svg(const Chart& chart, const std::vector<Series>& series);

/// One horizontal bar per entry, split into named segments (e.g. a method's stage times); the
/// same segment name gets the same colour in every bar.
struct Bar {
  std::string label;
  std::vector<std::pair<std::string, double>> segments;
};
std::string stacked_bars_svg(const std::string& title, const std::string& value_label,
                             const std::vector<Bar>& bars, int width = 720);

/// A horizontal colour bar from `colors` (sampled evenly, left to right), with tick labels at
/// `ticks` (value, text) placed over [lo, hi], and a caption.
std::string color_bar_svg(const std::vector<std::string>& colors, double lo, double hi,
                          const std::vector<std::pair<double, std::string>>& ticks,
                          const std::string& caption, int width = 360);

/// Shortest "%g" text of a number for tick labels (2–6 significant digits, within 0.5%).
std::string tick_label(double value);

/// Escapes &, <, >, ' and " for SVG/HTML text and attributes.
std::string xml_escape(const std::string& text);

/// Writes an SVG (or any text) file atomically (core/files.hpp); throws Error when it cannot.
void write_text_file(const std::filesystem::path& path, const std::string& text);

}  // namespace penumbra::plot
