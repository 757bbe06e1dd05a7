#include "penumbra/io/image_io.hpp"

#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfCompression.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfInputFile.h>
#include <OpenEXR/ImfOutputFile.h>
#include <zlib.h>

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

void check_layers_for_exr(const fs::path& path, const std::vector<FloatLayerView>& layers) {
  constexpr const char* what = "cannot write EXR";
  if (layers.empty()) fail(what, path, "no layers given");
  const int width = layers.front().pixels->width();
  const int height = layers.front().pixels->height();
  check_writable_size(what, path, width, height);
  std::set<std::string> names;
  for (const FloatLayerView& layer : layers) {
    if (layer.name.empty()) fail(what, path, "layer with an empty name");
    if (!names.insert(layer.name).second) fail(what, path, "duplicate layer " + quote(layer.name));
    if (layer.pixels->width() != width || layer.pixels->height() != height) {
      fail(what, path,
           "layer " + quote(layer.name) + " is " + std::to_string(layer.pixels->width()) + "x" +
               std::to_string(layer.pixels->height()) + ", expected " + std::to_string(width) +
               "x" + std::to_string(height));
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

namespace {

/// The 8-bit code of linear_to_srgb, by its definition (one powf per call).
uint8_t srgb8_by_formula(float linear) {
  const float encoded = linear_to_srgb(linear) * 255.0f + 0.5f;
  return static_cast<uint8_t>(std::clamp(static_cast<int>(encoded), 0, 255));
}

/// srgb8_by_formula as a table lookup, equal to it for every float. The code is a non-decreasing
/// step function of the linear value, so it is known exactly from the 255 floats where it steps
/// up: step[c] is the smallest float whose code is ≥ c, found by bisection over the bit patterns
/// of the floats in (0, 1) (positive floats order like their bits). A coarse table indexed by the
/// top 16 bits then gives the code at the start of each bucket of 2¹⁶ floats; no bucket holds two
/// steps (at most ≈ 0.66 codes a bucket, just above 0.5 where buckets are widest for the slope),
/// so one comparison with the next step finishes the lookup. Checked against the formula for
/// every float in [0, 1] (tests/test_image_io.cpp).
struct Srgb8Table {
  uint32_t step[257];  // bit patterns; step[0] = 0, step[256] = past every float
  uint8_t coarse[(0x3F800000u >> 16) + 1];

  Srgb8Table() {
    step[0] = 0;
    step[256] = 0xFFFFFFFFu;
    for (int c = 1; c < 256; ++c) {
      uint32_t lo = 0, hi = 0x3F800000u;  // code(lo) < c ≤ code(hi) = 255
      while (hi - lo > 1) {
        const uint32_t mid = lo + (hi - lo) / 2;
        (srgb8_by_formula(std::bit_cast<float>(mid)) >= c ? hi : lo) = mid;
      }
      step[c] = hi;
    }
    int c = 0;
    for (uint32_t bucket = 0; bucket < std::size(coarse); ++bucket) {
      while (step[c + 1] <= bucket << 16) ++c;
      coarse[bucket] = static_cast<uint8_t>(c);
    }
  }
};

}  // namespace

uint8_t linear_to_srgb8(float linear) {
  static const Srgb8Table table;
  if (!(linear > 0.0f)) return 0;  // also NaN
  if (linear >= 1.0f) return 255;
  const uint32_t bits = std::bit_cast<uint32_t>(linear);
  const int c = table.coarse[bits >> 16];
  return static_cast<uint8_t>(c + (bits >= table.step[c + 1]));
}

void write_png_rgb(const fs::path& path, const Image<Vec3>& linear_rgb) {
  const int width = linear_rgb.width();
  write_png_rgb(path, width, linear_rgb.height(),
                [&](int y, Vec3* out) { std::copy_n(&linear_rgb(0, y), width, out); });
}

void write_png_rgb(const fs::path& path, int width, int height,
                   const std::function<void(int y, Vec3* out)>& rows) {
  check_writable_size("cannot write PNG", path, width, height);
  std::vector<uint8_t> bytes(static_cast<size_t>(width) * height * 3);
  parallel_rows(height, [&](int y) {
    std::vector<Vec3> row(static_cast<size_t>(width));
    rows(y, row.data());
    uint8_t* to = bytes.data() + static_cast<size_t>(y) * width * 3;
    for (const Vec3& c : row) {
      *to++ = linear_to_srgb8(c.x);
      *to++ = linear_to_srgb8(c.y);
      *to++ = linear_to_srgb8(c.z);
    }
  });
  write_png_rgb8(path, width, height, bytes);
}

namespace {

void append_u32_be(std::string& out, uint32_t v) {
  const char bytes[4] = {static_cast<char>(v >> 24), static_cast<char>(v >> 16),
                         static_cast<char>(v >> 8), static_cast<char>(v)};
  out.append(bytes, 4);
}

/// One PNG chunk: length, type, data, CRC-32 of type and data.
void append_png_chunk(std::string& out, const char type[4], std::string_view data) {
  append_u32_be(out, static_cast<uint32_t>(data.size()));
  const size_t type_at = out.size();
  out.append(type, 4);
  out.append(data);
  uLong crc = crc32(0L, Z_NULL, 0);
  crc = crc32_z(crc, reinterpret_cast<const Bytef*>(out.data() + type_at), 4 + data.size());
  append_u32_be(out, static_cast<uint32_t>(crc));
}

/// A PNG (RGB, 8 bits per channel) of `rgb`, every row unfiltered (filter type 0: on renders the
/// unfiltered rows compress as well as filtered ones, 1024² beauty: 153 KB against 172 KB with
/// stb's per-row filter search) and one zlib stream at level 3 (≈ 10 ms and 147 KB for that
/// beauty, where stb's own deflate took ≈ 40 ms for 153 KB and zlib's default level 6 takes 30 ms
/// for 116 KB).
std::string encode_png_rgb8(int width, int height, const uint8_t* rgb) {
  const size_t row_bytes = static_cast<size_t>(width) * 3;
  z_stream z{};
  if (deflateInit(&z, 3) != Z_OK) throw Error("zlib: deflateInit failed");
  std::string idat;
  Bytef out[1 << 16];
  // Feeds `size` bytes (a row's filter byte, then its pixels), draining the output as it fills.
  const auto feed = [&](const uint8_t* data, size_t size, int flush) {
    z.next_in = const_cast<Bytef*>(data);
    z.avail_in = static_cast<uInt>(size);
    int status = Z_OK;
    do {
      z.next_out = out;
      z.avail_out = sizeof out;
      status = deflate(&z, flush);
      if (status == Z_STREAM_ERROR) break;
      idat.append(reinterpret_cast<const char*>(out), sizeof out - z.avail_out);
    } while (z.avail_out == 0 || (flush == Z_FINISH && status != Z_STREAM_END));
    return status != Z_STREAM_ERROR;
  };
  static const uint8_t kNoFilter = 0;
  bool ok = true;
  for (int y = 0; y < height && ok; ++y)
    ok =
        feed(&kNoFilter, 1, Z_NO_FLUSH) && feed(rgb + static_cast<size_t>(y) * row_bytes, row_bytes,
                                                y + 1 == height ? Z_FINISH : Z_NO_FLUSH);
  deflateEnd(&z);
  if (!ok) throw Error("zlib: deflate failed");

  std::string png("\x89PNG\r\n\x1a\n", 8);
  std::string ihdr;
  append_u32_be(ihdr, static_cast<uint32_t>(width));
  append_u32_be(ihdr, static_cast<uint32_t>(height));
  ihdr += std::string("\x08\x02\x00\x00\x00", 5);  // 8 bits, RGB, deflate, no filter, no interlace
  png.reserve(8 + 25 + 12 + idat.size() + 12);
  append_png_chunk(png, "IHDR", ihdr);
  // A chunk holds at most 2³¹ − 1 bytes: a larger stream continues in further IDAT chunks.
  constexpr size_t kMaxChunk = size_t{1} << 30;
  for (size_t at = 0; at < idat.size(); at += kMaxChunk)
    append_png_chunk(png, "IDAT", std::string_view(idat).substr(at, kMaxChunk));
  append_png_chunk(png, "IEND", {});
  return png;
}

}  // namespace

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
  // Encoded in memory, then written with every write checked (a full disk never reports success).
  std::string png;
  try {
    png = encode_png_rgb8(width, height, rgb.data());
  } catch (const Error& e) {
    fail(what, path, e.what());
  }
  write_all_bytes(what, path, png);
}

// -----------------------------------------------------------------------------------------------
// EXR

void write_exr(const fs::path& path, const std::vector<FloatLayer>& layers) {
  std::vector<FloatLayerView> views;
  views.reserve(layers.size());
  for (const FloatLayer& layer : layers) views.push_back({layer.name, &layer.pixels});
  write_exr_views(path, views);
}

void write_exr_views(const fs::path& path, const std::vector<FloatLayerView>& layers) {
  check_layers_for_exr(path, layers);
  const int width = layers.front().pixels->width();
  const int height = layers.front().pixels->height();
  try {
    Imf::Header header(width, height);
    header.compression() = Imf::ZIP_COMPRESSION;
    // zlib's fastest level: a 1024² visibility + mask file takes half the time of OpenEXR's
    // default (level 4: ≈ 54 → 28 ms) for twice the bytes (25 → 54 KB); the pixels are the same.
    header.zipCompressionLevel() = 1;
    Imf::FrameBuffer frame;
    for (const FloatLayerView& layer : layers) {
      header.channels().insert(layer.name, Imf::Channel(Imf::FLOAT));
      frame.insert(layer.name,
                   Imf::Slice::Make(Imf::FLOAT, layer.pixels->data(), header.dataWindow()));
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
