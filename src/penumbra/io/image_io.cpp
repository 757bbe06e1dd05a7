#include "penumbra/io/image_io.hpp"

#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfCompression.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfInputFile.h>
#include <OpenEXR/ImfOutputFile.h>
#include <stb/stb_image_write.h>

#include <algorithm>
#include <bit>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstring>
#include <fstream>
#include <limits>
#include <mutex>
#include <set>
#include <system_error>
#include <thread>

#include "penumbra/core/error.hpp"
#include "penumbra/core/files.hpp"
#include "penumbra/core/parallel.hpp"

namespace penumbra {
namespace {

namespace fs = std::filesystem;

// Guard against absurd sizes in malformed headers before allocating anything.
constexpr int64_t kMaxDimension = 1 << 20;
constexpr int64_t kMaxPixelsPerLayer = int64_t{1} << 28;

std::string quote_path(const fs::path& path) {
  return quote(path.string(), 200);
}

[[noreturn]] void fail(const char* what, const fs::path& path, const std::string& reason) {
  // Library messages (OpenEXR's in particular) may span lines; the CLI prints errors on one line.
  throw Error(std::string(what) + " " + quote_path(path) + ": " + one_line(reason));
}

/// Throws unless `path` names an existing regular file.
void require_regular_file(const char* what, const fs::path& path) {
  if (const std::string problem = regular_file_problem(path); !problem.empty())
    fail(what, path, problem);
}

std::vector<unsigned char> read_all_bytes(const char* what, const fs::path& path) {
  require_regular_file(what, path);
  std::error_code ec;
  const uintmax_t size = fs::file_size(path, ec);
  if (ec) fail(what, path, "cannot query file size: " + ec.message());
  if (size > static_cast<uintmax_t>(std::numeric_limits<std::streamsize>::max()))
    fail(what, path, "file too large");
  std::ifstream in(path, std::ios::binary);
  if (!in) fail(what, path, "cannot open file");
  std::vector<unsigned char> bytes(static_cast<size_t>(size));
  if (size > 0 &&
      !in.read(reinterpret_cast<char*>(bytes.data()), static_cast<std::streamsize>(size))) {
    fail(what, path, "read error");
  }
  return bytes;
}

/// Every write checked, and atomic (files.hpp): a full disk never leaves a truncated image.
void write_all_bytes(const char* what, const fs::path& path, const std::string& bytes) {
  try {
    write_text_file(path, bytes);
  } catch (const Error& e) {
    fail(what, path, e.what());
  }
}

std::string lowercase_extension(const fs::path& path) {
  std::string ext = path.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return ext;
}

// ---------------------------------------------------------------------------------------------
// PFM

uint32_t byteswap32(uint32_t v) {
  return ((v & 0x000000ffu) << 24) | ((v & 0x0000ff00u) << 8) | ((v & 0x00ff0000u) >> 8) |
         ((v & 0xff000000u) >> 24);
}

void append_float_le(std::string& out, float value) {
  uint32_t bits = std::bit_cast<uint32_t>(value);
  if constexpr (std::endian::native == std::endian::big) bits = byteswap32(bits);
  char bytes[4];
  std::memcpy(bytes, &bits, 4);
  out.append(bytes, 4);
}

float load_float(const unsigned char* p, bool little_endian) {
  uint32_t bits;
  std::memcpy(&bits, p, 4);
  const bool native_little = std::endian::native == std::endian::little;
  if (little_endian != native_little) bits = byteswap32(bits);
  return std::bit_cast<float>(bits);
}

std::string pfm_header(char kind, int width, int height) {
  return std::string("P") + kind + "\n" + std::to_string(width) + " " + std::to_string(height) +
         "\n-1.0\n";
}

void check_writable_size(const char* what, const fs::path& path, int width, int height) {
  if (width <= 0 || height <= 0) {
    fail(what, path,
         "image is empty (" + std::to_string(width) + "x" + std::to_string(height) + ")");
  }
}

bool is_pfm_space(unsigned char c) {
  return c == ' ' || c == '\t' || c == '\n' || c == '\r' || c == '\v' || c == '\f';
}

/// Minimal cursor over the PFM header text.
struct PfmHeaderParser {
  const std::vector<unsigned char>& bytes;
  size_t pos = 0;

  std::string next_token() {
    while (pos < bytes.size() && is_pfm_space(bytes[pos])) ++pos;
    const size_t begin = pos;
    // A header token is short; stop early on binary garbage.
    while (pos < bytes.size() && !is_pfm_space(bytes[pos]) && pos - begin < 64) ++pos;
    return std::string(bytes.begin() + static_cast<std::ptrdiff_t>(begin),
                       bytes.begin() + static_cast<std::ptrdiff_t>(pos));
  }
};

int parse_dimension(const char* what, const fs::path& path, const std::string& token,
                    const char* name) {
  int64_t value = 0;
  const auto [end, ec] = std::from_chars(token.data(), token.data() + token.size(), value);
  if (token.empty() || ec != std::errc() || end != token.data() + token.size())
    fail(what, path, std::string("malformed header: invalid ") + name + " " + quote(token));
  if (value <= 0 || value > kMaxDimension)
    fail(what, path, std::string("malformed header: ") + name + " out of range (" + token + ")");
  return static_cast<int>(value);
}

// ---------------------------------------------------------------------------------------------
// EXR

void check_layers_for_exr(const fs::path& path, const std::vector<FloatLayer>& layers) {
  constexpr const char* what = "cannot write EXR";
  if (layers.empty()) fail(what, path, "no layers given");
  const int width = layers.front().pixels.width();
  const int height = layers.front().pixels.height();
  check_writable_size(what, path, width, height);
  std::set<std::string> names;
  for (const FloatLayer& layer : layers) {
    if (layer.name.empty()) fail(what, path, "layer with an empty name");
    if (!names.insert(layer.name).second) fail(what, path, "duplicate layer " + quote(layer.name));
    if (layer.pixels.width() != width || layer.pixels.height() != height) {
      fail(what, path,
           "layer " + quote(layer.name) + " is " + std::to_string(layer.pixels.width()) + "x" +
               std::to_string(layer.pixels.height()) + ", expected " + std::to_string(width) + "x" +
               std::to_string(height));
    }
  }
}

}  // namespace

// -----------------------------------------------------------------------------------------------
// PNG

float linear_to_srgb(float linear) {
  if (!(linear > 0.0f)) return 0.0f;  // also NaN
  if (linear >= 1.0f) return 1.0f;
  if (linear <= 0.0031308f) return 12.92f * linear;
  return 1.055f * std::pow(linear, 1.0f / 2.4f) - 0.055f;
}

uint8_t linear_to_srgb8(float linear) {
  const float encoded = linear_to_srgb(linear) * 255.0f + 0.5f;
  return static_cast<uint8_t>(std::clamp(static_cast<int>(encoded), 0, 255));
}

void write_png_rgb(const fs::path& path, const Image<Vec3>& linear_rgb) {
  check_writable_size("cannot write PNG", path, linear_rgb.width(), linear_rgb.height());
  std::vector<uint8_t> bytes(linear_rgb.size() * 3);
  parallel_chunks(linear_rgb.size(), 1 << 14, [&](size_t begin, size_t end) {
    for (size_t i = begin; i < end; ++i) {
      const Vec3& c = linear_rgb[i];
      bytes[3 * i + 0] = linear_to_srgb8(c.x);
      bytes[3 * i + 1] = linear_to_srgb8(c.y);
      bytes[3 * i + 2] = linear_to_srgb8(c.z);
    }
  });
  write_png_rgb8(path, linear_rgb.width(), linear_rgb.height(), bytes);
}

void write_png_rgb8(const fs::path& path, int width, int height, const std::vector<uint8_t>& rgb) {
  constexpr const char* what = "cannot write PNG";
  check_writable_size(what, path, width, height);
  if (width > std::numeric_limits<int>::max() / 3) fail(what, path, "image too wide");
  const size_t expected = static_cast<size_t>(width) * static_cast<size_t>(height) * 3;
  if (rgb.size() != expected) {
    fail(what, path,
         "got " + std::to_string(rgb.size()) + " bytes for a " + std::to_string(width) + "x" +
             std::to_string(height) + " RGB image (expected " + std::to_string(expected) + ")");
  }
  // Encoded in memory, then written with every write checked: stbi_write_png ignores fwrite
  // errors and would report success on a full disk.
  std::string png;
  const auto append = [](void* context, void* data, int size) {
    static_cast<std::string*>(context)->append(static_cast<const char*>(data),
                                               static_cast<size_t>(size));
  };
  // No per-row filter search: on renders the unfiltered rows compress as well or better (a 1024²
  // beauty: 153 KB against 172 KB) in half the time. Set once; the encoder only reads it.
  static std::once_flag filter_once;
  std::call_once(filter_once, [] { stbi_write_force_png_filter = 0; });
  if (stbi_write_png_to_func(append, &png, width, height, 3, rgb.data(), width * 3) == 0)
    fail(what, path, "PNG encoding failed");
  write_all_bytes(what, path, png);
}

// -----------------------------------------------------------------------------------------------
// EXR

void write_exr(const fs::path& path, const std::vector<FloatLayer>& layers) {
  check_layers_for_exr(path, layers);
  const int width = layers.front().pixels.width();
  const int height = layers.front().pixels.height();
  try {
    Imf::Header header(width, height);
    header.compression() = Imf::ZIP_COMPRESSION;
    Imf::FrameBuffer frame;
    for (const FloatLayer& layer : layers) {
      header.channels().insert(layer.name, Imf::Channel(Imf::FLOAT));
      frame.insert(layer.name,
                   Imf::Slice::Make(Imf::FLOAT, layer.pixels.data(), header.dataWindow()));
    }
    // ZIP compresses blocks of 16 scanlines independently: OpenEXR's own threads share them.
    const int threads = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
    write_file_atomically(path, [&](const fs::path& temporary) {
      Imf::OutputFile file(temporary.string().c_str(), header, threads);
      file.setFrameBuffer(frame);
      file.writePixels(height);
    });  // OpenEXR throws on a failed write; the temporary is then removed
  } catch (const Error&) {
    throw;
  } catch (const std::exception& e) {
    fail("cannot write EXR", path, e.what());
  }
}

std::vector<FloatLayer> read_exr(const fs::path& path) {
  constexpr const char* what = "cannot read EXR";
  require_regular_file(what, path);
  try {
    Imf::InputFile file(path.string().c_str());
    const Imf::Header& header = file.header();
    const Imath::Box2i window = header.dataWindow();
    const int64_t width = int64_t{window.max.x} - window.min.x + 1;
    const int64_t height = int64_t{window.max.y} - window.min.y + 1;
    if (width <= 0 || height <= 0 || width > kMaxDimension || height > kMaxDimension ||
        width * height > kMaxPixelsPerLayer) {
      fail(what, path,
           "unsupported data window " + std::to_string(width) + "x" + std::to_string(height));
    }
    if (!file.isComplete()) fail(what, path, "file is incomplete (truncated?)");

    std::vector<FloatLayer> layers;
    Imf::FrameBuffer frame;
    const Imf::ChannelList& channels = header.channels();
    for (auto it = channels.begin(); it != channels.end(); ++it) {
      if (it.channel().xSampling != 1 || it.channel().ySampling != 1)
        fail(what, path, std::string("subsampled channel '") + it.name() + "' is not supported");
      layers.push_back(
          {it.name(), Image<float>(static_cast<int>(width), static_cast<int>(height))});
    }
    if (layers.empty()) fail(what, path, "file has no channels");
    for (FloatLayer& layer : layers)
      frame.insert(layer.name, Imf::Slice::Make(Imf::FLOAT, layer.pixels.data(), window));
    file.setFrameBuffer(frame);
    file.readPixels(window.min.y, window.max.y);
    return layers;
  } catch (const Error&) {
    throw;
  } catch (const std::exception& e) {
    fail(what, path, e.what());
  }
}

// -----------------------------------------------------------------------------------------------
// PFM

void write_pfm(const fs::path& path, const Image<float>& image) {
  check_writable_size("cannot write PFM", path, image.width(), image.height());
  std::string out = pfm_header('f', image.width(), image.height());
  out.reserve(out.size() + image.size() * 4);
  for (int y = image.height() - 1; y >= 0; --y)
    for (int x = 0; x < image.width(); ++x) append_float_le(out, image(x, y));
  write_all_bytes("cannot write PFM", path, out);
}

void write_pfm(const fs::path& path, const Image<Vec3>& image) {
  check_writable_size("cannot write PFM", path, image.width(), image.height());
  std::string out = pfm_header('F', image.width(), image.height());
  out.reserve(out.size() + image.size() * 12);
  for (int y = image.height() - 1; y >= 0; --y) {
    for (int x = 0; x < image.width(); ++x) {
      const Vec3& c = image(x, y);
      append_float_le(out, c.x);
      append_float_le(out, c.y);
      append_float_le(out, c.z);
    }
  }
  write_all_bytes("cannot write PFM", path, out);
}

std::vector<FloatLayer> read_pfm(const fs::path& path) {
  constexpr const char* what = "cannot read PFM";
  const std::vector<unsigned char> bytes = read_all_bytes(what, path);
  if (bytes.empty()) fail(what, path, "empty file");
  if (bytes.size() < 3 || bytes[0] != 'P' || (bytes[1] != 'F' && bytes[1] != 'f') ||
      !is_pfm_space(bytes[2])) {
    fail(what, path, "not a PFM file (magic must be 'PF' or 'Pf')");
  }
  const int channels = bytes[1] == 'F' ? 3 : 1;

  PfmHeaderParser parser{bytes, 2};
  const int width = parse_dimension(what, path, parser.next_token(), "width");
  const int height = parse_dimension(what, path, parser.next_token(), "height");
  const std::string scale_token = parser.next_token();
  double scale = 0.0;
  const auto [end, ec] =
      std::from_chars(scale_token.data(), scale_token.data() + scale_token.size(), scale);
  if (scale_token.empty() || ec != std::errc() || end != scale_token.data() + scale_token.size() ||
      !std::isfinite(scale) || scale == 0.0) {
    fail(what, path, "malformed header: invalid scale " + quote(scale_token));
  }
  // Exactly one whitespace character separates the header from the raster.
  if (parser.pos >= bytes.size() || !is_pfm_space(bytes[parser.pos]))
    fail(what, path, "malformed header: no pixel data after the scale");
  const size_t data_begin = parser.pos + 1;
  const bool little_endian = scale < 0.0;

  const uint64_t pixel_count = static_cast<uint64_t>(width) * static_cast<uint64_t>(height);
  if (pixel_count > static_cast<uint64_t>(kMaxPixelsPerLayer)) fail(what, path, "image too large");
  const uint64_t needed = pixel_count * static_cast<uint64_t>(channels) * 4;
  const uint64_t available = bytes.size() - data_begin;
  if (available < needed) {
    fail(what, path,
         "truncated pixel data (" + std::to_string(available) + " bytes, expected " +
             std::to_string(needed) + ")");
  }

  static constexpr const char* kColourNames[3] = {"R", "G", "B"};
  std::vector<FloatLayer> layers;
  for (int c = 0; c < channels; ++c)
    layers.push_back({channels == 1 ? "Y" : kColourNames[c], Image<float>(width, height)});
  const unsigned char* p = bytes.data() + data_begin;
  for (int row = 0; row < height; ++row) {
    const int y = height - 1 - row;  // PFM rows run bottom-to-top
    for (int x = 0; x < width; ++x) {
      for (int c = 0; c < channels; ++c) {
        layers[static_cast<size_t>(c)].pixels(x, y) = load_float(p, little_endian);
        p += 4;
      }
    }
  }
  return layers;
}

std::vector<FloatLayer> read_float_image(const fs::path& path) {
  const std::string ext = lowercase_extension(path);
  if (ext == ".exr") return read_exr(path);
  if (ext == ".pfm") return read_pfm(path);
  fail("cannot read image", path, "unsupported format " + quote(ext) + " (expected .exr or .pfm)");
}

}  // namespace penumbra
