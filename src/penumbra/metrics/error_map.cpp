#include "penumbra/metrics/error_map.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <vector>

#include "penumbra/core/error.hpp"
#include "penumbra/io/image_io.hpp"

// stb_easy_font is a header of static functions; we do not use all of them.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wunused-function"
#pragma GCC diagnostic ignored "-Wsign-compare"
#pragma GCC diagnostic ignored "-Wmissing-field-initializers"
#include <stb/stb_easy_font.h>
#pragma GCC diagnostic pop

namespace penumbra {
namespace {

// matplotlib's viridis sampled at t = 0, 1/8, ..., 1.
constexpr Rgb8 kViridis[] = {{68, 1, 84},    {71, 44, 122},  {59, 81, 139},
                             {44, 113, 142}, {33, 144, 141}, {39, 173, 129},
                             {92, 200, 99},  {170, 220, 50}, {253, 231, 37}};
constexpr int kViridisSize = static_cast<int>(std::size(kViridis));

// Legend layout in font units (multiplied by the text scale).
constexpr int kPadTop = 4;
constexpr int kBarHeight = 10;
constexpr int kTickLength = 3;
constexpr int kTextGap = 2;
constexpr int kTextHeight = 8;  // digits and '.' fit in 7 rows; one row of slack
constexpr int kPadBottom = 4;
constexpr int kPadSide = 4;
constexpr int kLegendUnits =
    kPadTop + kBarHeight + kTickLength + kTextGap + kTextHeight + kPadBottom;

int text_scale(int width) {
  return width >= 512 ? 2 : 1;
}

/// RGB canvas with clipped drawing.
struct Canvas {
  int width = 0, height = 0;
  std::vector<uint8_t> rgb;

  Canvas(int w, int h) : width(w), height(h), rgb(static_cast<size_t>(w) * h * 3, 0) {}

  void set(int x, int y, const Rgb8& c) {
    if (x < 0 || y < 0 || x >= width || y >= height) return;
    const size_t i = (static_cast<size_t>(y) * width + x) * 3;
    rgb[i] = c[0];
    rgb[i + 1] = c[1];
    rgb[i + 2] = c[2];
  }
  void fill_rect(int x0, int y0, int x1, int y1, const Rgb8& c) {  // [x0,x1) x [y0,y1)
    x0 = std::max(x0, 0);
    y0 = std::max(y0, 0);
    x1 = std::min(x1, width);
    y1 = std::min(y1, height);
    for (int y = y0; y < y1; ++y)
      for (int x = x0; x < x1; ++x) set(x, y, c);
  }
};

int text_width_units(const std::string& text) {
  std::string copy = text;  // stb_easy_font takes char*
  return stb_easy_font_width(copy.data());
}

/// Rasterizes `text` with its top-left corner at (x, y), each font unit `scale` pixels.
void draw_text(Canvas& canvas, int x, int y, int scale, const std::string& text, const Rgb8& c) {
  std::string copy = text;
  // 4 vertices x 16 bytes per quad; a character has at most a few dozen quads.
  std::vector<char> buffer(64 * 64 * (text.size() + 1));
  const int quads = stb_easy_font_print(0.0f, 0.0f, copy.data(), nullptr, buffer.data(),
                                        static_cast<int>(buffer.size()));
  for (int q = 0; q < quads; ++q) {
    float lo_x = 1e9f, lo_y = 1e9f, hi_x = -1e9f, hi_y = -1e9f;
    for (int v = 0; v < 4; ++v) {
      float px, py;
      std::memcpy(&px, buffer.data() + (q * 4 + v) * 16, sizeof(float));
      std::memcpy(&py, buffer.data() + (q * 4 + v) * 16 + 4, sizeof(float));
      lo_x = std::min(lo_x, px);
      lo_y = std::min(lo_y, py);
      hi_x = std::max(hi_x, px);
      hi_y = std::max(hi_y, py);
    }
    canvas.fill_rect(x + static_cast<int>(std::lround(lo_x)) * scale,
                     y + static_cast<int>(std::lround(lo_y)) * scale,
                     x + static_cast<int>(std::lround(hi_x)) * scale,
                     y + static_cast<int>(std::lround(hi_y)) * scale, c);
  }
}

void draw_legend(Canvas& canvas, int top, double scale_max) {
  const int s = text_scale(canvas.width);
  canvas.fill_rect(0, top, canvas.width, canvas.height, kErrorMapLegendBackground);

  // Colour bar over [bar_x0, bar_x1); full width on images too narrow for side padding.
  int bar_x0 = kPadSide * s, bar_x1 = canvas.width - kPadSide * s;
  if (bar_x1 - bar_x0 < 2) bar_x0 = 0, bar_x1 = canvas.width;
  const int bar_y0 = top + kPadTop * s, bar_y1 = bar_y0 + kBarHeight * s;
  const int span = std::max(bar_x1 - 1 - bar_x0, 1);
  for (int x = bar_x0; x < bar_x1; ++x) {
    canvas.fill_rect(x, bar_y0, x + 1, bar_y1,
                     error_colormap(static_cast<double>(x - bar_x0) / span));
  }

  // Ticks and labels at 0, max/2, max. Labels that would overlap a previous one are dropped.
  struct Tick {
    int x;
    std::string label;
    int align;  // -1 left-aligned at x, 0 centred, +1 right-aligned
  };
  const Tick ticks[] = {{bar_x0, error_map_label(0.0), -1},
                        {bar_x1 - 1, error_map_label(scale_max), +1},
                        {bar_x0 + span / 2, error_map_label(scale_max / 2.0), 0}};
  const int text_y = bar_y1 + (kTickLength + kTextGap) * s;
  std::vector<std::pair<int, int>> used;  // horizontal extents of drawn labels
  for (const Tick& tick : ticks) {
    canvas.fill_rect(tick.x - (s - 1) / 2, bar_y1, tick.x - (s - 1) / 2 + s,
                     bar_y1 + kTickLength * s, kErrorMapLegendText);
    // stb_easy_font's width includes the advance after the last glyph (1 unit of spacing).
    const int w = std::max(text_width_units(tick.label) - 1, 1) * s;
    int x0 = tick.align < 0 ? tick.x : tick.align > 0 ? tick.x + 1 - w : tick.x - w / 2;
    x0 = std::clamp(x0, 0, std::max(canvas.width - w, 0));
    const int x1 = x0 + w;
    const bool overlaps = std::any_of(used.begin(), used.end(), [&](const auto& e) {
      return x0 < e.second + 2 * s && e.first < x1 + 2 * s;
    });
    if (overlaps) continue;
    used.emplace_back(x0, x1);
    draw_text(canvas, x0, text_y, s, tick.label, kErrorMapLegendText);
  }
}

}  // namespace

Rgb8 error_colormap(double t) {
  if (!(t > 0.0)) return kViridis[0];  // also NaN
  if (t >= 1.0) return kViridis[kViridisSize - 1];
  const double f = t * (kViridisSize - 1);
  const int i = std::min(static_cast<int>(f), kViridisSize - 2);
  const double a = f - i;
  Rgb8 out{};
  for (int c = 0; c < 3; ++c) {
    const double v = (1.0 - a) * kViridis[i][c] + a * kViridis[i + 1][c];
    out[c] = static_cast<uint8_t>(std::clamp(std::lround(v), 0L, 255L));
  }
  return out;
}

int error_map_legend_height(int width) {
  return kLegendUnits * text_scale(width);
}

std::string error_map_label(double value) {
  if (value == 0.0) return "0";
  std::string best;
  for (int precision = 2; precision <= 6; ++precision) {
    char buffer[64];
    std::snprintf(buffer, sizeof(buffer), "%.*g", precision, value);
    best = buffer;
    const double parsed = std::strtod(buffer, nullptr);
    const bool close = std::abs(parsed - value) <= 0.006 * std::abs(value);
    if (close && best.find('e') == std::string::npos) return best;
  }
  return best;
}

void write_error_map_png(const std::filesystem::path& path, const Image<float>& abs_error,
                         double scale_max, const Image<float>* mask) {
  const std::string where = "cannot write error map " + quote(path.string(), 200) + ": ";
  if (abs_error.empty()) throw Error(where + "error image is empty");
  if (!std::isfinite(scale_max) || !(scale_max > 0.0))
    throw Error(where + "scale_max must be finite and > 0 (got " + std::to_string(scale_max) + ")");
  if (mask && (mask->width() != abs_error.width() || mask->height() != abs_error.height())) {
    throw Error(where + "mask is " + std::to_string(mask->width()) + "x" +
                std::to_string(mask->height()) + ", error image is " +
                std::to_string(abs_error.width()) + "x" + std::to_string(abs_error.height()));
  }

  const int width = abs_error.width(), height = abs_error.height();
  Canvas canvas(width, height + error_map_legend_height(width));
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      const float e = abs_error(x, y);
      if (mask && !((*mask)(x, y) > 0.5f))
        canvas.set(x, y, kErrorMapMaskedColor);
      else if (std::isnan(e))
        canvas.set(x, y, kErrorMapNanColor);
      else
        canvas.set(x, y, error_colormap(static_cast<double>(e) / scale_max));
    }
  }
  draw_legend(canvas, height, scale_max);
  write_png_rgb8(path, canvas.width, canvas.height, canvas.rgb);
}

}  // namespace penumbra
