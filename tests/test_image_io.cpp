#include <gtest/gtest.h>
#include <stb/stb_image.h>
#include <unistd.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <string>
#include <vector>

#include "penumbra/core/error.hpp"
#include "penumbra/io/image_io.hpp"

namespace fs = std::filesystem;
using penumbra::Error;
using penumbra::FloatLayer;
using penumbra::Image;
using penumbra::Vec3;

namespace {

class ImageIoTest : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = fs::temp_directory_path() / ("penumbra_io_" + std::string(info->test_suite_name()) +
                                        "_" + info->name() + "_" + std::to_string(::getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override {
    std::error_code ec;
    fs::remove_all(dir_, ec);
  }

  fs::path file(const std::string& name) const { return dir_ / name; }

  static void write_bytes(const fs::path& path, const std::string& bytes) {
    std::ofstream out(path, std::ios::binary);
    out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  }
  static std::string read_bytes(const fs::path& path) {
    std::ifstream in(path, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), {});
  }

  /// Expects `fn` to throw penumbra::Error with a one-line message naming `path`.
  static void expect_error_naming(const std::function<void()>& fn, const fs::path& path) {
    try {
      fn();
      ADD_FAILURE() << "no penumbra::Error thrown for " << path;
    } catch (const Error& e) {
      const std::string message = e.what();
      EXPECT_NE(message.find(path.filename().string()), std::string::npos) << message;
      EXPECT_EQ(message.find('\n'), std::string::npos) << message;
    } catch (const std::exception& e) {
      ADD_FAILURE() << "wrong exception type for " << path << ": " << e.what();
    }
  }

  fs::path dir_;
};

uint32_t bits(float f) {
  return std::bit_cast<uint32_t>(f);
}

Image<float> ramp(int w, int h, float offset) {
  Image<float> image(w, h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) image(x, y) = offset + static_cast<float>(x) + 10.0f * y;
  return image;
}

void expect_bit_exact(const Image<float>& a, const Image<float>& b) {
  ASSERT_EQ(a.width(), b.width());
  ASSERT_EQ(a.height(), b.height());
  for (int y = 0; y < a.height(); ++y)
    for (int x = 0; x < a.width(); ++x)
      EXPECT_EQ(bits(a(x, y)), bits(b(x, y))) << "at (" << x << ", " << y << ")";
}

// ----------------------------------------------------------------------------------------------
// EXR

TEST_F(ImageIoTest, ExrRoundTripThreeLayersIsBitExact) {
  const int w = 5, h = 3;  // non-square: catches transposition
  Image<float> light0 = ramp(w, h, 0.0f);
  light0(1, 0) = 1.0f / 3.0f;
  light0(2, 0) = std::numeric_limits<float>::denorm_min();
  light0(3, 0) = -0.0f;
  light0(4, 0) = std::numeric_limits<float>::max();
  light0(0, 2) = std::numeric_limits<float>::quiet_NaN();
  light0(1, 2) = std::numeric_limits<float>::infinity();
  Image<float> light0_r = ramp(w, h, 0.125f);
  light0_r(2, 1) = 0.1f;
  Image<float> mask(w, h, 1.0f);
  mask(0, 0) = 0.0f;

  const fs::path path = file("layers.exr");
  penumbra::write_exr(path, {{"light0", light0}, {"light0.R", light0_r}, {"mask", mask}});
  ASSERT_TRUE(fs::exists(path));

  const std::vector<FloatLayer> layers = penumbra::read_exr(path);
  ASSERT_EQ(layers.size(), 3u);
  EXPECT_EQ(layers[0].name, "light0");
  EXPECT_EQ(layers[1].name, "light0.R");
  EXPECT_EQ(layers[2].name, "mask");
  expect_bit_exact(layers[0].pixels, light0);
  expect_bit_exact(layers[1].pixels, light0_r);
  expect_bit_exact(layers[2].pixels, mask);
  EXPECT_EQ(layers[2].pixels(0, 0), 0.0f);
  EXPECT_EQ(layers[0].pixels(3, 1), 3.0f + 10.0f);

  // read_float_image dispatches on the extension.
  const std::vector<FloatLayer> again = penumbra::read_float_image(path);
  ASSERT_EQ(again.size(), 3u);
  expect_bit_exact(again[1].pixels, light0_r);
}

TEST_F(ImageIoTest, ExrChannelsComeBackSortedByName) {
  const fs::path path = file("order.exr");
  penumbra::write_exr(path, {{"mask", Image<float>(2, 2, 1.0f)}, {"a", Image<float>(2, 2, 2.0f)}});
  const auto layers = penumbra::read_exr(path);
  ASSERT_EQ(layers.size(), 2u);
  EXPECT_EQ(layers[0].name, "a");
  EXPECT_EQ(layers[0].pixels(1, 1), 2.0f);
  EXPECT_EQ(layers[1].name, "mask");
  EXPECT_EQ(layers[1].pixels(1, 1), 1.0f);
}

TEST_F(ImageIoTest, ExrWriteRejectsBadLayers) {
  const fs::path path = file("bad.exr");
  expect_error_naming([&] { penumbra::write_exr(path, {}); }, path);
  expect_error_naming(
      [&] {
        penumbra::write_exr(path, {{"a", Image<float>(2, 2)}, {"b", Image<float>(3, 2)}});
      },
      path);
  expect_error_naming(
      [&] {
        penumbra::write_exr(path, {{"a", Image<float>(2, 2)}, {"a", Image<float>(2, 2)}});
      },
      path);
  expect_error_naming([&] { penumbra::write_exr(path, {{"", Image<float>(2, 2)}}); }, path);
  expect_error_naming([&] { penumbra::write_exr(path, {{"a", Image<float>()}}); }, path);
  const fs::path no_dir = file("missing_dir/x.exr");
  expect_error_naming([&] { penumbra::write_exr(no_dir, {{"a", Image<float>(2, 2)}}); }, no_dir);
}

TEST_F(ImageIoTest, MalformedExrThrows) {
  const fs::path missing = file("missing.exr");
  expect_error_naming([&] { penumbra::read_exr(missing); }, missing);

  const fs::path empty = file("empty.exr");
  write_bytes(empty, "");
  expect_error_naming([&] { penumbra::read_exr(empty); }, empty);

  const fs::path garbage = file("garbage.exr");
  std::string noise;
  for (int i = 0; i < 4096; ++i) noise.push_back(static_cast<char>((i * 7919 + 13) & 0xff));
  write_bytes(garbage, noise);
  expect_error_naming([&] { penumbra::read_exr(garbage); }, garbage);

  // A PFM renamed to .exr: wrong magic.
  const fs::path wrong_magic = file("wrong_magic.exr");
  penumbra::write_pfm(wrong_magic, Image<float>(4, 4, 0.5f));
  expect_error_naming([&] { penumbra::read_exr(wrong_magic); }, wrong_magic);

  // A valid EXR cut in half.
  const fs::path valid = file("valid.exr");
  Image<float> noisy(64, 64);
  for (size_t i = 0; i < noisy.size(); ++i) noisy[i] = static_cast<float>((i * 2654435761u) % 1000);
  penumbra::write_exr(valid, {{"Y", noisy}});
  const std::string bytes = read_bytes(valid);
  ASSERT_GT(bytes.size(), 100u);
  const fs::path truncated = file("truncated.exr");
  write_bytes(truncated, bytes.substr(0, bytes.size() / 2));
  expect_error_naming([&] { penumbra::read_exr(truncated); }, truncated);

  const fs::path directory = file("dir.exr");
  fs::create_directories(directory);
  expect_error_naming([&] { penumbra::read_exr(directory); }, directory);
}

// ----------------------------------------------------------------------------------------------
// PFM

TEST_F(ImageIoTest, PfmGreyRoundTripPreservesOrientation) {
  Image<float> image(3, 2, 0.0f);
  image(1, 0) = 42.0f;  // top row
  image(0, 1) = -7.5f;  // bottom-left
  image(2, 1) = 1.0f / 3.0f;
  const fs::path path = file("grey.pfm");
  penumbra::write_pfm(path, image);

  // On disk: header, then rows bottom-to-top, little endian.
  const std::string bytes = read_bytes(path);
  const std::string header = "Pf\n3 2\n-1.0\n";
  ASSERT_EQ(bytes.size(), header.size() + 6 * 4);
  EXPECT_EQ(bytes.substr(0, header.size()), header);
  const auto le_float_at = [&](size_t index) {
    const auto* p =
        reinterpret_cast<const unsigned char*>(bytes.data() + header.size() + 4 * index);
    const uint32_t v =
        uint32_t{p[0]} | uint32_t{p[1]} << 8 | uint32_t{p[2]} << 16 | uint32_t{p[3]} << 24;
    return std::bit_cast<float>(v);
  };
  EXPECT_EQ(le_float_at(0), -7.5f);  // first stored pixel = bottom-left
  EXPECT_EQ(le_float_at(4), 42.0f);  // second stored row = top row, x = 1

  const auto layers = penumbra::read_pfm(path);
  ASSERT_EQ(layers.size(), 1u);
  EXPECT_EQ(layers[0].name, "Y");
  expect_bit_exact(layers[0].pixels, image);
  EXPECT_EQ(layers[0].pixels(1, 0), 42.0f);
  EXPECT_EQ(layers[0].pixels(1, 1), 0.0f);
}

TEST_F(ImageIoTest, PfmColourRoundTripPreservesOrientation) {
  Image<Vec3> image(4, 3, Vec3(0.0f));
  image(1, 0) = Vec3(1.0f, 2.0f, 3.0f);
  image(3, 2) = Vec3(-1.0f, 0.25f, 1e-30f);
  image(0, 1) = Vec3(0.1f, 0.2f, 0.3f);
  const fs::path path = file("colour.PFM");  // extension match is case-insensitive
  penumbra::write_pfm(path, image);
  EXPECT_EQ(read_bytes(path).substr(0, 3), "PF\n");

  const auto layers = penumbra::read_float_image(path);
  ASSERT_EQ(layers.size(), 3u);
  EXPECT_EQ(layers[0].name, "R");
  EXPECT_EQ(layers[1].name, "G");
  EXPECT_EQ(layers[2].name, "B");
  for (int c = 0; c < 3; ++c) {
    ASSERT_EQ(layers[c].pixels.width(), 4);
    ASSERT_EQ(layers[c].pixels.height(), 3);
    for (int y = 0; y < 3; ++y)
      for (int x = 0; x < 4; ++x)
        EXPECT_EQ(bits(layers[c].pixels(x, y)), bits(image(x, y)[c]))
            << "channel " << c << " at (" << x << ", " << y << ")";
  }
  EXPECT_EQ(layers[1].pixels(1, 0), 2.0f);
  EXPECT_EQ(layers[0].pixels(3, 2), -1.0f);
}

TEST_F(ImageIoTest, PfmReadsBigEndian) {
  // 2x1 grey, positive scale = big endian.
  std::string bytes = "Pf\n2 1\n1.0\n";
  for (float f : {1.5f, -2.0f}) {
    const uint32_t v = std::bit_cast<uint32_t>(f);
    for (int shift = 24; shift >= 0; shift -= 8) bytes.push_back(static_cast<char>(v >> shift));
  }
  const fs::path path = file("big.pfm");
  write_bytes(path, bytes);
  const auto layers = penumbra::read_pfm(path);
  ASSERT_EQ(layers.size(), 1u);
  EXPECT_EQ(layers[0].pixels(0, 0), 1.5f);
  EXPECT_EQ(layers[0].pixels(1, 0), -2.0f);
}

TEST_F(ImageIoTest, MalformedPfmThrows) {
  const fs::path missing = file("missing.pfm");
  expect_error_naming([&] { penumbra::read_pfm(missing); }, missing);
  expect_error_naming([&] { penumbra::read_float_image(missing); }, missing);

  const auto expect_bad = [&](const std::string& name, const std::string& bytes) {
    const fs::path path = file(name);
    write_bytes(path, bytes);
    expect_error_naming([&] { penumbra::read_pfm(path); }, path);
  };
  expect_bad("empty.pfm", "");
  std::string garbage;
  for (int i = 0; i < 300; ++i) garbage.push_back(static_cast<char>((i * 131 + 7) & 0xff));
  expect_bad("garbage.pfm", garbage);
  expect_bad("wrong_magic.pfm", "P6\n2 2\n255\n" + std::string(12, '\0'));
  expect_bad("magic_only.pfm", "PF");
  expect_bad("no_size.pfm", "Pf\n");
  expect_bad("bad_width.pfm", "Pf\nabc 2\n-1.0\n" + std::string(64, '\0'));
  expect_bad("zero_width.pfm", "Pf\n0 2\n-1.0\n");
  expect_bad("negative_height.pfm", "Pf\n2 -2\n-1.0\n" + std::string(64, '\0'));
  expect_bad("huge.pfm", "Pf\n1000000 1000000\n-1.0\n" + std::string(64, '\0'));
  expect_bad("bad_scale.pfm", "Pf\n2 2\nx\n" + std::string(16, '\0'));
  expect_bad("zero_scale.pfm", "Pf\n2 2\n0\n" + std::string(16, '\0'));
  expect_bad("no_data.pfm", "Pf\n2 2\n-1.0");
  // Header promises 2x2 grey = 16 bytes; 15 present.
  expect_bad("truncated.pfm", "Pf\n2 2\n-1.0\n" + std::string(15, '\0'));
  // Colour needs 3x as much.
  expect_bad("truncated_colour.pfm", "PF\n2 2\n-1.0\n" + std::string(16, '\0'));

  // And a valid written file cut short.
  const fs::path valid = file("valid.pfm");
  penumbra::write_pfm(valid, Image<Vec3>(8, 8, Vec3(0.5f)));
  const std::string bytes = read_bytes(valid);
  expect_bad("cut.pfm", bytes.substr(0, bytes.size() - 1));
}

TEST_F(ImageIoTest, UnsupportedExtensionThrows) {
  const fs::path path = file("image.png");
  write_bytes(path, "not really");
  expect_error_naming([&] { penumbra::read_float_image(path); }, path);
  const fs::path no_ext = file("image");
  write_bytes(no_ext, "x");
  expect_error_naming([&] { penumbra::read_float_image(no_ext); }, no_ext);
}

TEST_F(ImageIoTest, PfmWriteRejectsEmptyImageAndBadDirectory) {
  const fs::path path = file("empty_out.pfm");
  expect_error_naming([&] { penumbra::write_pfm(path, Image<float>()); }, path);
  const fs::path no_dir = file("missing_dir/x.pfm");
  expect_error_naming([&] { penumbra::write_pfm(no_dir, Image<float>(2, 2)); }, no_dir);
}

// ----------------------------------------------------------------------------------------------
// PNG

TEST(SrgbEncoding, PiecewiseTransfer) {
  EXPECT_EQ(penumbra::linear_to_srgb(0.0f), 0.0f);
  EXPECT_EQ(penumbra::linear_to_srgb(1.0f), 1.0f);
  EXPECT_NEAR(penumbra::linear_to_srgb(0.002f), 12.92f * 0.002f, 1e-7f);  // linear segment
  EXPECT_NEAR(penumbra::linear_to_srgb(0.5f), 0.735357f, 1e-5f);
  EXPECT_NEAR(penumbra::linear_to_srgb(0.2f), 0.484529f, 1e-5f);
  EXPECT_EQ(penumbra::linear_to_srgb8(0.5f), 188);
  EXPECT_EQ(penumbra::linear_to_srgb8(0.2f), 124);
  EXPECT_EQ(penumbra::linear_to_srgb8(0.0015654f), 5);
  EXPECT_EQ(penumbra::linear_to_srgb8(1.0f), 255);
  EXPECT_EQ(penumbra::linear_to_srgb8(7.0f), 255);
  EXPECT_EQ(penumbra::linear_to_srgb8(-1.0f), 0);
  EXPECT_EQ(penumbra::linear_to_srgb8(std::numeric_limits<float>::quiet_NaN()), 0);
}

// linear_to_srgb8 is a table lookup (image_io.cpp): it must give the formula's code for every
// float. The whole range [0, 1] was checked once (1.07e9 floats, no difference); here every 61st
// bit pattern and ±300 patterns around each of the 255 steps, in well under a second.
TEST(SrgbEncoding, TableEqualsFormulaForEveryFloat) {
  const auto formula = [](float x) {
    const float encoded = penumbra::linear_to_srgb(x) * 255.0f + 0.5f;
    return std::clamp(static_cast<int>(encoded), 0, 255);
  };
  const auto check = [&](uint32_t bits) {
    const float x = std::bit_cast<float>(bits);
    if (penumbra::linear_to_srgb8(x) != formula(x)) {
      ADD_FAILURE() << "bits " << bits << " (" << x << "): table "
                    << int{penumbra::linear_to_srgb8(x)} << ", formula " << formula(x);
      return false;
    }
    return true;
  };
  constexpr uint32_t kOne = 0x3F800000u;
  for (uint32_t b = 0; b <= kOne + 64; b += 61)
    if (!check(b)) return;
  int steps = 0;
  for (uint32_t b = 1; b <= kOne; ++b) {
    // Bisect to each step of the formula, then check its neighbourhood densely.
    const int code = formula(std::bit_cast<float>(b - 1));
    if (code == 255) break;
    uint32_t lo = b - 1, hi = kOne;
    while (hi - lo > 1) {
      const uint32_t mid = lo + (hi - lo) / 2;
      (formula(std::bit_cast<float>(mid)) > code ? hi : lo) = mid;
    }
    ++steps;
    for (uint32_t k = hi - std::min<uint32_t>(hi, 300); k <= hi + 300; ++k)
      if (!check(k)) return;
    b = hi;
  }
  EXPECT_EQ(steps, 255);
}

/// A 128² image of every kind of value a render holds (ramps, noise, out of range, NaN) written
/// as PNG and decoded again: the file holds exactly linear_to_srgb8 of every channel.
TEST_F(ImageIoTest, PngDecodesToTheEncodedImage) {
  Image<Vec3> image(128, 128);
  uint32_t state = 12345;
  const auto noise = [&] {
    state = state * 1664525u + 1013904223u;
    return static_cast<float>(state >> 8) / static_cast<float>(1u << 24);
  };
  for (int y = 0; y < 128; ++y)
    for (int x = 0; x < 128; ++x)
      image(x, y) = y < 64 ? Vec3(x / 127.0f, y / 63.0f, 1.1f * noise() - 0.05f)
                           : Vec3(noise(), x == y ? std::numeric_limits<float>::quiet_NaN() : 0.25f,
                                  noise() * 0.004f);
  const fs::path path = file("decoded.png");
  penumbra::write_png_rgb(path, image);
  int w = 0, h = 0, n = 0;
  unsigned char* data = stbi_load(path.string().c_str(), &w, &h, &n, 3);
  ASSERT_NE(data, nullptr) << stbi_failure_reason();
  ASSERT_EQ(w, 128);
  ASSERT_EQ(h, 128);
  EXPECT_EQ(n, 3);
  int differing = 0;
  for (size_t i = 0; i < image.size(); ++i)
    for (int c = 0; c < 3; ++c)
      differing += data[3 * i + c] != penumbra::linear_to_srgb8(image[i][c]);
  stbi_image_free(data);
  EXPECT_EQ(differing, 0);
}

TEST_F(ImageIoTest, PngRgbIsSrgbEncodedAndReadable) {
  Image<Vec3> image(3, 2, Vec3(0.0f));
  image(1, 0) = Vec3(0.5f, 1.0f, 0.2f);
  image(2, 1) = Vec3(2.0f, -1.0f, 0.0015654f);
  const fs::path path = file("rgb.png");
  penumbra::write_png_rgb(path, image);

  int w = 0, h = 0, n = 0;
  unsigned char* data = stbi_load(path.string().c_str(), &w, &h, &n, 3);
  ASSERT_NE(data, nullptr) << stbi_failure_reason();
  EXPECT_EQ(w, 3);
  EXPECT_EQ(h, 2);
  const auto px = [&](int x, int y, int c) { return int{data[(y * w + x) * 3 + c]}; };
  EXPECT_EQ(px(1, 0, 0), 188);
  EXPECT_EQ(px(1, 0, 1), 255);
  EXPECT_EQ(px(1, 0, 2), 124);
  EXPECT_EQ(px(2, 1, 0), 255);
  EXPECT_EQ(px(2, 1, 1), 0);
  EXPECT_EQ(px(2, 1, 2), 5);
  EXPECT_EQ(px(0, 0, 0), 0);
  stbi_image_free(data);
}

TEST_F(ImageIoTest, PngRgb8WritesBytesVerbatimAndValidatesSize) {
  const std::vector<uint8_t> rgb = {1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12};  // 2x2
  const fs::path path = file("rgb8.png");
  penumbra::write_png_rgb8(path, 2, 2, rgb);
  int w = 0, h = 0, n = 0;
  unsigned char* data = stbi_load(path.string().c_str(), &w, &h, &n, 3);
  ASSERT_NE(data, nullptr);
  ASSERT_EQ(w * h, 4);
  EXPECT_EQ(std::vector<uint8_t>(data, data + 12), rgb);
  stbi_image_free(data);

  expect_error_naming([&] { penumbra::write_png_rgb8(path, 2, 3, rgb); }, path);
  expect_error_naming([&] { penumbra::write_png_rgb8(path, 0, 2, {}); }, path);
  expect_error_naming([&] { penumbra::write_png_rgb(path, Image<Vec3>()); }, path);
  const fs::path no_dir = file("missing_dir/x.png");
  expect_error_naming([&] { penumbra::write_png_rgb8(no_dir, 2, 2, rgb); }, no_dir);
}

}  // namespace
