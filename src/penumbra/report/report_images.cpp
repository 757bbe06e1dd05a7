#include "penumbra/report/report_images.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "penumbra/io/image_io.hpp"
#include "penumbra/metrics/error_map.hpp"

namespace penumbra::report {

namespace {

using Rgb = std::array<uint8_t, 3>;

constexpr Rgb kMasked = kErrorMapMaskedColor;
// ColorBrewer RdBu (reversed): blue for negative, white at 0, red for positive.
constexpr Rgb kDiverging[] = {
    {5, 48, 97}, {67, 147, 195}, {247, 247, 247}, {214, 96, 77}, {103, 0, 31}};

Rgb diverging(double t) {  // t in [-1, 1]
  const double u = (std::clamp(t, -1.0, 1.0) + 1.0) * 0.5 * (std::size(kDiverging) - 1);
  const int i = std::min(static_cast<int>(u), static_cast<int>(std::size(kDiverging)) - 2);
  const double f = u - i;
  Rgb c{};
  for (int k = 0; k < 3; ++k)
    c[k] = static_cast<uint8_t>(
        std::lround(kDiverging[i][k] + f * (kDiverging[i + 1][k] - kDiverging[i][k])));
  return c;
}

std::string hex(const Rgb& c) {
  char b[8];
  std::snprintf(b, sizeof b, "#%02x%02x%02x", c[0], c[1], c[2]);
  return b;
}

template <typename F>
Rgb8Image map_error(const Image<float>& e, const Image<float>& mask, F color) {
  Rgb8Image out(e.width(), e.height());
  for (size_t i = 0; i < e.size(); ++i) out[i] = mask[i] > 0.5f ? color(e[i]) : kMasked;
  return out;
}

}  // namespace

Rgb8Image abs_error_picture(const Image<float>& e, const Image<float>& mask, double scale) {
  return map_error(e, mask, [&](float v) {
    return std::isfinite(v) ? error_colormap(std::fabs(v) / scale) : kErrorMapNanColor;
  });
}

Rgb8Image signed_error_picture(const Image<float>& e, const Image<float>& mask, double scale) {
  return map_error(e, mask, [&](float v) {
    return std::isfinite(v) ? diverging(v / scale) : kErrorMapNanColor;
  });
}

Rgb8Image srgb_picture(const Image<Vec3>& rgb) {
  Rgb8Image out(rgb.width(), rgb.height());
  for (size_t i = 0; i < rgb.size(); ++i)
    out[i] = {linear_to_srgb8(rgb[i].x), linear_to_srgb8(rgb[i].y), linear_to_srgb8(rgb[i].z)};
  return out;
}

std::vector<std::string> abs_error_colors() {
  std::vector<std::string> out;
  for (int i = 0; i <= 8; ++i) out.push_back(hex(error_colormap(i / 8.0)));
  return out;
}

std::vector<std::string> signed_error_colors() {
  std::vector<std::string> out;
  for (const Rgb& c : kDiverging) out.push_back(hex(c));
  return out;
}

double common_error_scale(const std::vector<const Image<float>*>& errors,
                          const Image<float>& mask) {
  std::vector<double> p99;  // per method with visible errors
  for (const Image<float>* e : errors) {
    std::vector<float> visible;
    for (size_t i = 0; i < e->size(); ++i)
      if (mask[i] > 0.5f && std::fabs((*e)[i]) > 1.0f / 1024.0f)
        visible.push_back(std::fabs((*e)[i]));
    if (visible.empty()) continue;
    const size_t k = std::min(visible.size() - 1, visible.size() * 99 / 100);
    std::nth_element(visible.begin(), visible.begin() + static_cast<long>(k), visible.end());
    p99.push_back(visible[k]);
  }
  if (p99.empty()) return 1.0 / 255.0;
  std::sort(p99.begin(), p99.end());
  const double p = p99[(p99.size() - 1) / 2];
  const double mag = std::pow(10.0, std::floor(std::log10(p)));
  const double r = p / mag;
  const double nice = (r <= 1.0 ? 1.0 : r <= 2.0 ? 2.0 : r <= 5.0 ? 5.0 : 10.0) * mag;
  return std::clamp(nice, 1.0 / 255.0, 1.0);
}

CropRect penumbra_window(const Image<float>& v, const Image<float>& mask) {
  const int w = v.width(), h = v.height();
  CropRect r;
  r.size = std::min({std::max(8, std::min(w, h) / 4), w, h});
  // Summed-area table of penumbra pixels.
  std::vector<int> sat(static_cast<size_t>(w + 1) * (h + 1), 0);
  const auto at = [&](int x, int y) -> int& { return sat[static_cast<size_t>(y) * (w + 1) + x]; };
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const size_t i = static_cast<size_t>(y) * w + x;
      const int p = mask[i] > 0.5f && v[i] > 0.02f && v[i] < 0.98f ? 1 : 0;
      at(x + 1, y + 1) = p + at(x, y + 1) + at(x + 1, y) - at(x, y);
    }
  r.x = (w - r.size) / 2;
  r.y = (h - r.size) / 2;
  int best = 0;
  const int stride = std::max(1, r.size / 8);
  for (int y = 0; y + r.size <= h; y += stride)
    for (int x = 0; x + r.size <= w; x += stride) {
      const int n = at(x + r.size, y + r.size) - at(x, y + r.size) - at(x + r.size, y) + at(x, y);
      if (n > best) best = n, r.x = x, r.y = y;
    }
  return r;
}

Rgb8Image crop_zoom(const Rgb8Image& picture, const CropRect& rect, int zoom) {
  Rgb8Image out(rect.size * zoom, rect.size * zoom);
  for (int y = 0; y < out.height(); ++y)
    for (int x = 0; x < out.width(); ++x) out(x, y) = picture(rect.x + x / zoom, rect.y + y / zoom);
  return out;
}

void write_picture(const std::filesystem::path& path, const Rgb8Image& picture) {
  std::vector<uint8_t> bytes;
  bytes.reserve(picture.size() * 3);
  for (const auto& c : picture.pixels()) bytes.insert(bytes.end(), c.begin(), c.end());
  write_png_rgb8(path, picture.width(), picture.height(), bytes);
}

}  // namespace penumbra::report
