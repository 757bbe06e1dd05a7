#include <gtest/gtest.h>
#include <stb/stb_image.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <limits>
#include <set>
#include <string>

#include "penumbra/core/error.hpp"
#include "penumbra/metrics/error_map.hpp"
#include "penumbra/metrics/error_metrics.hpp"

namespace fs = std::filesystem;
using penumbra::Error;
using penumbra::ErrorStats;
using penumbra::Image;

namespace {

// Reference (4x4):        Test = reference except at 5 pixels (|diff| in brackets):
//   1   1   1   1           (3,0) 0.5        [0.5]    unshadowed
//   1  .5  .5   1           (1,1) 0.75       [0.25]   shadowed
//   1   0   0   1           (2,1) 0.53125    [1/32]   shadowed
//   1   1   1   1           (2,2) 0.125      [0.125]  shadowed
//                           (0,3) 1 - 1/512  [1/512]  unshadowed, below 1/255
// (1,2) is shadowed with zero error. All values are exact in float.
Image<float> reference_4x4() {
  Image<float> ref(4, 4, 1.0f);
  ref(1, 1) = 0.5f;
  ref(2, 1) = 0.5f;
  ref(1, 2) = 0.0f;
  ref(2, 2) = 0.0f;
  return ref;
}

Image<float> test_4x4() {
  Image<float> test = reference_4x4();
  test(3, 0) = 0.5f;
  test(1, 1) = 0.75f;
  test(2, 1) = 0.53125f;
  test(2, 2) = 0.125f;
  test(0, 3) = 1.0f - 1.0f / 512.0f;
  return test;
}

TEST(CompareImages, HandComputedStatistics) {
  const ErrorStats s = penumbra::compare_images(reference_4x4(), test_4x4());
  EXPECT_EQ(s.pixels, 16u);
  EXPECT_EQ(s.shadowed_pixels, 4u);
  // sum |d| = 0.5 + 0.25 + 0.125 + 0.03125 + 0.001953125 = 0.908203125
  EXPECT_DOUBLE_EQ(s.mean_abs, 0.908203125 / 16.0);
  // shadowed: (0.25 + 0.03125 + 0 + 0.125) / 4
  EXPECT_DOUBLE_EQ(s.mean_abs_shadowed, 0.40625 / 4.0);
  // sum d^2 = 0.25 + 0.0625 + 0.015625 + 0.0009765625 + 0.000003814697265625
  const double mse = 0.329105377197265625 / 16.0;
  EXPECT_DOUBLE_EQ(s.rmse, std::sqrt(mse));
  EXPECT_NEAR(s.rmse, 0.1434193, 1e-6);
  EXPECT_NEAR(s.psnr, 16.86785, 1e-4);
  EXPECT_DOUBLE_EQ(s.max_abs, 0.5);
  EXPECT_DOUBLE_EQ(s.frac_over_1_255, 4.0 / 16.0);  // 0.5, 0.25, 0.125, 1/32 (not 1/512)
  EXPECT_DOUBLE_EQ(s.frac_over_1_16, 3.0 / 16.0);   // 0.5, 0.25, 0.125
}

TEST(CompareImages, MaskRestrictsCountedPixels) {
  Image<float> mask(4, 4, 0.0f);
  for (int y = 0; y < 4; ++y)
    for (int x = 0; x < 2; ++x) mask(x, y) = 1.0f;  // left half only
  const ErrorStats s = penumbra::compare_images(reference_4x4(), test_4x4(), &mask);
  EXPECT_EQ(s.pixels, 8u);
  EXPECT_EQ(s.shadowed_pixels, 2u);                       // (1,1) and (1,2)
  EXPECT_DOUBLE_EQ(s.mean_abs, (0.25 + 1.0 / 512) / 8);   // (1,1) and (0,3)
  EXPECT_DOUBLE_EQ(s.mean_abs_shadowed, (0.25 + 0) / 2);  // (1,1) and (1,2)
  EXPECT_DOUBLE_EQ(s.max_abs, 0.25);                      // 0.5 at (3,0) is masked out
  EXPECT_DOUBLE_EQ(s.rmse, std::sqrt((0.0625 + 1.0 / (512.0 * 512.0)) / 8));
  EXPECT_NEAR(s.psnr, 21.07183, 1e-4);
  EXPECT_DOUBLE_EQ(s.frac_over_1_255, 1.0 / 8);
  EXPECT_DOUBLE_EQ(s.frac_over_1_16, 1.0 / 8);
}

TEST(CompareImages, MaskThresholdIsStrictlyAboveHalf) {
  const Image<float> half(4, 4, 0.5f);
  const ErrorStats s = penumbra::compare_images(reference_4x4(), test_4x4(), &half);
  EXPECT_EQ(s.pixels, 0u);
  EXPECT_EQ(s.shadowed_pixels, 0u);
  EXPECT_EQ(s.mean_abs, 0.0);
  EXPECT_EQ(s.max_abs, 0.0);
  EXPECT_EQ(s.psnr, penumbra::kPsnrCap);
  Image<float> one = half;
  one(3, 0) = 0.51f;
  const ErrorStats t = penumbra::compare_images(reference_4x4(), test_4x4(), &one);
  EXPECT_EQ(t.pixels, 1u);
  EXPECT_DOUBLE_EQ(t.mean_abs, 0.5);
  EXPECT_DOUBLE_EQ(t.psnr, 10.0 * std::log10(4.0));
}

TEST(CompareImages, ShadowedThreshold) {
  Image<float> ref(3, 1, 1.0f);
  ref(0, 0) = 1.0f - 5e-5f;  // within 1e-4 of 1: lit
  ref(1, 0) = 1.0f - 2e-4f;  // shadowed (penumbra)
  Image<float> test(3, 1, 1.0f);
  test(1, 0) = 0.5f;
  const ErrorStats s = penumbra::compare_images(ref, test);
  EXPECT_EQ(s.shadowed_pixels, 1u);
  EXPECT_NEAR(s.mean_abs_shadowed, 0.5 - 2e-4, 1e-6);

  // No shadowed pixel at all -> 0, not NaN.
  const ErrorStats lit =
      penumbra::compare_images(Image<float>(2, 2, 1.0f), Image<float>(2, 2, 0.f));
  EXPECT_EQ(lit.shadowed_pixels, 0u);
  EXPECT_EQ(lit.mean_abs_shadowed, 0.0);
  EXPECT_DOUBLE_EQ(lit.mean_abs, 1.0);
  EXPECT_DOUBLE_EQ(lit.psnr, 0.0);
}

TEST(CompareImages, IdenticalImagesGiveCappedFinitePsnr) {
  const ErrorStats s = penumbra::compare_images(reference_4x4(), reference_4x4());
  EXPECT_EQ(s.psnr, 999.0);
  EXPECT_EQ(s.rmse, 0.0);
  EXPECT_EQ(s.mean_abs, 0.0);
  EXPECT_EQ(s.frac_over_1_255, 0.0);
  const std::string dumped = penumbra::to_json(s).dump();
  EXPECT_EQ(dumped.find("null"), std::string::npos) << dumped;  // nlohmann writes inf/nan as null
  EXPECT_NE(dumped.find("999"), std::string::npos) << dumped;
}

TEST(CompareImages, JsonHasExactlyTheDocumentedKeys) {
  const ErrorStats s = penumbra::compare_images(reference_4x4(), test_4x4());
  const nlohmann::json j = penumbra::to_json(s);
  ASSERT_TRUE(j.is_object());
  std::set<std::string> keys;
  for (const auto& [key, value] : j.items()) keys.insert(key);
  EXPECT_EQ(keys, (std::set<std::string>{"mean_abs_shadowed", "mean_abs", "rmse", "max_abs", "psnr",
                                         "frac_over_1_255", "frac_over_1_16", "pixels",
                                         "shadowed_pixels"}));
  EXPECT_DOUBLE_EQ(j.at("mean_abs").get<double>(), s.mean_abs);
  EXPECT_DOUBLE_EQ(j.at("mean_abs_shadowed").get<double>(), s.mean_abs_shadowed);
  EXPECT_DOUBLE_EQ(j.at("rmse").get<double>(), s.rmse);
  EXPECT_DOUBLE_EQ(j.at("max_abs").get<double>(), 0.5);
  EXPECT_DOUBLE_EQ(j.at("psnr").get<double>(), s.psnr);
  EXPECT_DOUBLE_EQ(j.at("frac_over_1_255").get<double>(), 0.25);
  EXPECT_DOUBLE_EQ(j.at("frac_over_1_16").get<double>(), 0.1875);
  EXPECT_EQ(j.at("pixels").get<size_t>(), 16u);
  EXPECT_EQ(j.at("shadowed_pixels").get<size_t>(), 4u);
  EXPECT_TRUE(j.at("pixels").is_number_unsigned());
}

TEST(CompareImages, NonFiniteValuesThrowNamingThePixel) {
  Image<float> test = test_4x4();
  test(2, 1) = std::numeric_limits<float>::quiet_NaN();
  try {
    penumbra::compare_images(reference_4x4(), test);
    FAIL() << "no Error for NaN";
  } catch (const Error& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find("(2, 1)"), std::string::npos) << message;
    EXPECT_NE(message.find("NaN"), std::string::npos) << message;
    EXPECT_NE(message.find("test"), std::string::npos) << message;
  }
  Image<float> ref = reference_4x4();
  ref(0, 3) = std::numeric_limits<float>::quiet_NaN();
  EXPECT_THROW(penumbra::compare_images(ref, test_4x4()), Error);
  ref(0, 3) = std::numeric_limits<float>::infinity();
  EXPECT_THROW(penumbra::compare_images(ref, test_4x4()), Error);
  EXPECT_THROW(penumbra::abs_difference(reference_4x4(), test), Error);
  Image<float> mask(4, 4, 1.0f);
  mask(1, 1) = std::numeric_limits<float>::quiet_NaN();
  EXPECT_THROW(penumbra::compare_images(reference_4x4(), test_4x4(), &mask), Error);
}

TEST(CompareImages, SizeMismatchThrows) {
  EXPECT_THROW(penumbra::compare_images(Image<float>(4, 4), Image<float>(4, 3)), Error);
  EXPECT_THROW(penumbra::compare_images(Image<float>(4, 4), Image<float>(3, 4)), Error);
  const Image<float> mask(2, 8, 1.0f);  // same pixel count, different shape
  EXPECT_THROW(penumbra::compare_images(Image<float>(4, 4), Image<float>(4, 4), &mask), Error);
  EXPECT_THROW(penumbra::abs_difference(Image<float>(4, 4), Image<float>(5, 4)), Error);
}

TEST(AbsDifference, PerPixel) {
  const Image<float> diff = penumbra::abs_difference(reference_4x4(), test_4x4());
  ASSERT_EQ(diff.width(), 4);
  ASSERT_EQ(diff.height(), 4);
  EXPECT_EQ(diff(3, 0), 0.5f);
  EXPECT_EQ(diff(1, 1), 0.25f);
  EXPECT_EQ(diff(2, 1), 0.03125f);
  EXPECT_EQ(diff(2, 2), 0.125f);
  EXPECT_EQ(diff(0, 3), 1.0f / 512.0f);
  EXPECT_EQ(diff(0, 0), 0.0f);
  EXPECT_EQ(diff(1, 2), 0.0f);
}

// ----------------------------------------------------------------------------------------------
// Error map

class ErrorMapTest : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = fs::temp_directory_path() /
           ("penumbra_metrics_" + std::string(info->name()) + "_" + std::to_string(::getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override {
    std::error_code ec;
    fs::remove_all(dir_, ec);
  }

  struct Png {
    int w = 0, h = 0;
    std::vector<unsigned char> rgb;
    penumbra::Rgb8 at(int x, int y) const {
      const size_t i = (static_cast<size_t>(y) * w + x) * 3;
      return {rgb[i], rgb[i + 1], rgb[i + 2]};
    }
  };
  static Png load(const fs::path& path) {
    Png png;
    int n = 0;
    unsigned char* data = stbi_load(path.string().c_str(), &png.w, &png.h, &n, 3);
    if (!data) {
      ADD_FAILURE() << "stbi_load failed: " << stbi_failure_reason();
      return png;
    }
    png.rgb.assign(data, data + static_cast<size_t>(png.w) * png.h * 3);
    stbi_image_free(data);
    return png;
  }

  fs::path dir_;
};

TEST(ErrorColormap, EndpointsAndMidpoint) {
  EXPECT_EQ(penumbra::error_colormap(0.0), (penumbra::Rgb8{68, 1, 84}));
  EXPECT_EQ(penumbra::error_colormap(-3.0), (penumbra::Rgb8{68, 1, 84}));
  EXPECT_EQ(penumbra::error_colormap(0.5), (penumbra::Rgb8{33, 144, 141}));
  EXPECT_EQ(penumbra::error_colormap(1.0), (penumbra::Rgb8{253, 231, 37}));
  EXPECT_EQ(penumbra::error_colormap(50.0), (penumbra::Rgb8{253, 231, 37}));
  // Linear between samples: halfway between t=0 and t=1/8.
  EXPECT_EQ(penumbra::error_colormap(1.0 / 16), (penumbra::Rgb8{70, 23, 103}));
}

TEST(ErrorMapLabel, Formatting) {
  EXPECT_EQ(penumbra::error_map_label(0.0), "0");
  EXPECT_EQ(penumbra::error_map_label(1.0 / 255), "0.0039");
  EXPECT_EQ(penumbra::error_map_label(0.5), "0.5");
  EXPECT_EQ(penumbra::error_map_label(1.0), "1");
  EXPECT_EQ(penumbra::error_map_label(1.0 / 16), "0.0625");
  EXPECT_EQ(penumbra::error_map_label(100.0), "100");
}

TEST_F(ErrorMapTest, WritesFalseColourWithLegend) {
  const double scale = 1.0 / 255;
  Image<float> error(8, 6, 0.0f);
  error(3, 2) = static_cast<float>(scale / 2);
  error(7, 5) = 10.0f;  // saturates
  Image<float> mask(8, 6, 1.0f);
  mask(5, 0) = 0.0f;
  const fs::path path = dir_ / "error.png";
  penumbra::write_error_map_png(path, error, scale, &mask);

  const Png png = load(path);
  EXPECT_EQ(png.w, 8);
  EXPECT_EQ(png.h, 6 + penumbra::error_map_legend_height(8));
  EXPECT_GT(png.h, 6);
  EXPECT_EQ(png.at(0, 0), penumbra::error_colormap(0.0));
  EXPECT_EQ(png.at(0, 0), (penumbra::Rgb8{68, 1, 84}));
  EXPECT_EQ(png.at(3, 2), penumbra::error_colormap(0.5));
  EXPECT_EQ(png.at(7, 5), penumbra::error_colormap(1.0));
  EXPECT_EQ(png.at(5, 0), penumbra::kErrorMapMaskedColor);
}

TEST_F(ErrorMapTest, LegendHasBarAndReadableText) {
  const int w = 256, h = 16;
  const fs::path path = dir_ / "legend.png";
  penumbra::write_error_map_png(path, Image<float>(w, h, 0.0f), 1.0 / 255, nullptr);
  const Png png = load(path);
  ASSERT_EQ(png.w, w);
  const int legend = penumbra::error_map_legend_height(w);
  ASSERT_EQ(png.h, h + legend);
  EXPECT_GE(legend, 24);

  // The colour bar runs from the 0 colour on the left to the max colour on the right.
  int bar_row = -1;
  for (int y = h; y < png.h && bar_row < 0; ++y)
    if (png.at(w / 2, y) != penumbra::kErrorMapLegendBackground) bar_row = y;
  ASSERT_GE(bar_row, h);
  int left = 0;
  while (left < w && png.at(left, bar_row) == penumbra::kErrorMapLegendBackground) ++left;
  int right = w - 1;
  while (right > 0 && png.at(right, bar_row) == penumbra::kErrorMapLegendBackground) --right;
  EXPECT_EQ(png.at(left, bar_row), penumbra::error_colormap(0.0));
  EXPECT_EQ(png.at(right, bar_row), penumbra::error_colormap(1.0));

  // Text pixels exist at the left (label "0"), middle and right (label "0.0039").
  int text_left = 0, text_mid = 0, text_right = 0;
  for (int y = bar_row; y < png.h; ++y) {
    for (int x = 0; x < w; ++x) {
      if (png.at(x, y) != penumbra::kErrorMapLegendText) continue;
      if (x < w / 4)
        ++text_left;
      else if (x < 3 * w / 4)
        ++text_mid;
      else
        ++text_right;
    }
  }
  EXPECT_GT(text_left, 10);
  EXPECT_GT(text_mid, 10);
  EXPECT_GT(text_right, 30);
}

TEST_F(ErrorMapTest, LegendScalesUpForWideImages) {
  EXPECT_EQ(penumbra::error_map_legend_height(512), 2 * penumbra::error_map_legend_height(511));
  const fs::path path = dir_ / "wide.png";
  penumbra::write_error_map_png(path, Image<float>(512, 4, 0.0f), 0.25, nullptr);
  const Png png = load(path);
  EXPECT_EQ(png.w, 512);
  EXPECT_EQ(png.h, 4 + penumbra::error_map_legend_height(512));
}

TEST_F(ErrorMapTest, TinyImagesStillWork) {
  const fs::path path = dir_ / "tiny.png";
  penumbra::write_error_map_png(path, Image<float>(1, 1, 0.0f), 1.0, nullptr);
  const Png png = load(path);
  EXPECT_EQ(png.w, 1);
  EXPECT_EQ(png.at(0, 0), penumbra::error_colormap(0.0));
}

TEST_F(ErrorMapTest, RejectsBadArguments) {
  const fs::path path = dir_ / "bad.png";
  const Image<float> error(4, 4, 0.0f);
  EXPECT_THROW(penumbra::write_error_map_png(path, error, 0.0, nullptr), Error);
  EXPECT_THROW(penumbra::write_error_map_png(path, error, -1.0, nullptr), Error);
  EXPECT_THROW(penumbra::write_error_map_png(path, error, std::nan(""), nullptr), Error);
  const Image<float> mask(4, 3, 1.0f);
  EXPECT_THROW(penumbra::write_error_map_png(path, error, 1.0, &mask), Error);
  EXPECT_THROW(penumbra::write_error_map_png(path, Image<float>(), 1.0, nullptr), Error);
  EXPECT_THROW(penumbra::write_error_map_png(dir_ / "no_dir" / "x.png", error, 1.0, nullptr),
               Error);
  EXPECT_FALSE(fs::exists(path));
}

}  // namespace
