#include "penumbra/metrics/error_metrics.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "penumbra/core/error.hpp"

namespace penumbra {
namespace {

std::string size_string(const Image<float>& image) {
  return std::to_string(image.width()) + "x" + std::to_string(image.height());
}

void check_same_size(const Image<float>& ref, const Image<float>& other, const char* other_name) {
  if (ref.width() != other.width() || ref.height() != other.height()) {
    throw Error(std::string("image size mismatch: reference is ") + size_string(ref) + ", " +
                other_name + " is " + size_string(other));
  }
}

void check_finite(const Image<float>& image, const char* name) {
  for (int y = 0; y < image.height(); ++y) {
    for (int x = 0; x < image.width(); ++x) {
      const float v = image(x, y);
      if (!std::isfinite(v)) {
        throw Error(std::string("non-finite value (") + (std::isnan(v) ? "NaN" : "Inf") + ") in " +
                    name + " image at pixel (" + std::to_string(x) + ", " + std::to_string(y) +
                    ")");
      }
    }
  }
}

}  // namespace

ErrorStats compare_images(const Image<float>& ref, const Image<float>& test,
                          const Image<float>* mask) {
  check_same_size(ref, test, "test");
  if (mask) check_same_size(ref, *mask, "mask");
  check_finite(ref, "reference");
  check_finite(test, "test");
  if (mask) check_finite(*mask, "mask");

  double sum_abs = 0.0, sum_sq = 0.0, max_abs = 0.0, sum_abs_shadowed = 0.0;
  size_t count = 0, shadowed = 0, over_1_255 = 0, over_1_16 = 0;
  for (size_t i = 0; i < ref.size(); ++i) {
    if (mask && !((*mask)[i] > 0.5f)) continue;
    const double r = ref[i];
    const double d = std::abs(static_cast<double>(test[i]) - r);
    ++count;
    sum_abs += d;
    sum_sq += d * d;
    max_abs = std::max(max_abs, d);
    if (d > 1.0 / 255.0) ++over_1_255;
    if (d > 1.0 / 16.0) ++over_1_16;
    if (r < 1.0 - kShadowedThreshold) {
      ++shadowed;
      sum_abs_shadowed += d;
    }
  }

  ErrorStats stats;
  stats.pixels = count;
  stats.shadowed_pixels = shadowed;
  stats.max_abs = max_abs;
  if (count > 0) {
    const double n = static_cast<double>(count);
    stats.mean_abs = sum_abs / n;
    const double mse = sum_sq / n;
    stats.rmse = std::sqrt(mse);
    stats.psnr = mse > 0.0 ? std::min(kPsnrCap, 10.0 * std::log10(1.0 / mse)) : kPsnrCap;
    stats.frac_over_1_255 = static_cast<double>(over_1_255) / n;
    stats.frac_over_1_16 = static_cast<double>(over_1_16) / n;
  } else {
    stats.psnr = kPsnrCap;
  }
  if (shadowed > 0) stats.mean_abs_shadowed = sum_abs_shadowed / static_cast<double>(shadowed);
  return stats;
}

nlohmann::json to_json(const ErrorStats& stats) {
  return nlohmann::json{{"mean_abs_shadowed", stats.mean_abs_shadowed},
                        {"mean_abs", stats.mean_abs},
                        {"rmse", stats.rmse},
                        {"max_abs", stats.max_abs},
                        {"psnr", stats.psnr},
                        {"frac_over_1_255", stats.frac_over_1_255},
                        {"frac_over_1_16", stats.frac_over_1_16},
                        {"pixels", stats.pixels},
                        {"shadowed_pixels", stats.shadowed_pixels}};
}

Image<float> abs_difference(const Image<float>& ref, const Image<float>& test) {
  check_same_size(ref, test, "test");
  check_finite(ref, "reference");
  check_finite(test, "test");
  Image<float> diff(ref.width(), ref.height());
  for (size_t i = 0; i < ref.size(); ++i) diff[i] = std::abs(test[i] - ref[i]);
  return diff;
}

}  // namespace penumbra
