// The scene file's typed JSON fields (strict numbers, vectors, colours, objects with a fixed set of
// keys, one-line errors naming the JSON path) and its texture cache: shared by the scene loader
// and the animation loader. Internal to src/penumbra/scene.
#pragma once

#include <stb/stb_image.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <limits>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <set>
#include <string>
#include <vector>

#include "penumbra/core/error.hpp"
#include "penumbra/core/files.hpp"
#include "penumbra/core/suggest.hpp"
#include "penumbra/scene/scene.hpp"

namespace penumbra::scene_json {

using json = nlohmann::json;
namespace fs = std::filesystem;

using json = nlohmann::json;
namespace fs = std::filesystem;

[[noreturn]] inline void fail(const std::string& where, const std::string& what) {
  throw Error(where.empty() ? what : where + ": " + what);
}

inline std::string join(const std::vector<std::string>& items, const std::string& sep = ", ") {
  std::string out;
  for (const std::string& s : items) out += (out.empty() ? "" : sep) + s;
  return out;
}

inline std::string in_quotes(const std::string& s) {
  return quote(s, 200);
}

// ---- typed values -----------------------------------------------------------------------------

/// What a value is, for "expected X (got Y)" messages.
inline std::string describe(const json& v) {
  switch (v.type()) {
    case json::value_t::null:
      return "null";
    case json::value_t::boolean:
      return v.get<bool>() ? "true" : "false";
    case json::value_t::string: {
      std::string s = v.dump();
      if (s.size() > 40) s = s.substr(0, 36) + "...\"";
      return "the string " + s;
    }
    case json::value_t::array:
      return "an array of " + std::to_string(v.size()) + " elements";
    case json::value_t::object:
      return "an object";
    case json::value_t::number_integer:
    case json::value_t::number_unsigned:
    case json::value_t::number_float:
      return "the number " + v.dump();
    default:
      return "an unsupported value";
  }
}

[[noreturn]] inline void expected(const std::string& path, const std::string& what,
                                  const json& got) {
  fail(path, "expected " + what + " (got " + describe(got) + ")");
}

inline double as_double(const json& v, const std::string& path, double limit) {
  if (!v.is_number()) expected(path, "a number", v);
  const double d = v.get<double>();
  if (!std::isfinite(d)) fail(path, "must be a finite number");
  if (std::fabs(d) > limit) fail(path, "number out of range");
  return d;
}

inline float as_number(const json& v, const std::string& path) {
  return static_cast<float>(
      as_double(v, path, static_cast<double>(std::numeric_limits<float>::max())));
}

/// Positions are read in double and moved by −origin before they are rounded to float, so a scene
/// far from the world origin keeps the precision it would have next to it (recentre_scene).
/// Beyond 1e15 even double cannot place a detail of the scene's own size.
inline constexpr double kMaxPosition = 1e15;

inline double as_coordinate(const json& v, const std::string& path) {
  if (v.is_number() && std::isfinite(v.get<double>()) && std::fabs(v.get<double>()) > kMaxPosition)
    fail(path, "beyond 1e15 in magnitude (unsupported range)");
  return as_double(v, path, kMaxPosition);
}

inline Vec3 as_position(const json& v, const std::string& path, const DVec3& origin) {
  if (!v.is_array() || v.size() != 3) expected(path, "an array of 3 numbers", v);
  Vec3 out;
  for (int i = 0; i < 3; ++i)
    out[i] =
        static_cast<float>(as_coordinate(v[i], path + "[" + std::to_string(i) + "]") - origin[i]);
  return out;
}

inline float as_positive(const json& v, const std::string& path) {
  const float x = as_number(v, path);
  if (!(x > 0.0f)) fail(path, "must be positive");
  return x;
}

inline int as_int(const json& v, const std::string& path, int lo, int hi) {
  if (!v.is_number_integer()) expected(path, "an integer", v);
  const std::string range = "must be in " + std::to_string(lo) + ".." + std::to_string(hi);
  if (v.is_number_unsigned()) {
    const uint64_t x = v.get<uint64_t>();
    if (x > static_cast<uint64_t>(hi) || static_cast<int64_t>(x) < lo) fail(path, range);
    return static_cast<int>(x);
  }
  const int64_t x = v.get<int64_t>();
  if (x < lo || x > hi) fail(path, range);
  return static_cast<int>(x);
}

inline bool as_bool(const json& v, const std::string& path) {
  if (!v.is_boolean()) expected(path, "true or false", v);
  return v.get<bool>();
}

inline std::string as_string(const json& v, const std::string& path) {
  if (!v.is_string()) expected(path, "a string", v);
  std::string s = v.get<std::string>();
  if (s.empty()) fail(path, "must not be empty");
  // A path would be cut at the NUL by the file system calls, and load another file.
  if (s.find('\0') != std::string::npos) fail(path, "must not contain a NUL character (\\u0000)");
  return s;
}

inline Vec3 as_vec3(const json& v, const std::string& path) {
  if (!v.is_array() || v.size() != 3) expected(path, "an array of 3 numbers", v);
  Vec3 out;
  for (int i = 0; i < 3; ++i) out[i] = as_number(v[i], path + "[" + std::to_string(i) + "]");
  return out;
}

/// A non-negative colour: one number (grey) or [r, g, b].
inline Vec3 as_color(const json& v, const std::string& path, bool allow_scalar) {
  Vec3 c;
  if (allow_scalar && v.is_number()) {
    c = Vec3(as_number(v, path));
  } else if (v.is_array()) {
    c = as_vec3(v, path);
  } else {
    expected(path, allow_scalar ? "a number or an array of 3 numbers" : "an array of 3 numbers", v);
  }
  if (c.x < 0.0f || c.y < 0.0f || c.z < 0.0f) fail(path, "must not be negative");
  return c;
}

/// A non-empty array of `plural` (e.g. "lights"), one of which is a `singular`.
inline const json& as_array(const json& v, const std::string& path, const std::string& plural,
                            const std::string& singular) {
  if (!v.is_array()) expected(path, "an array of " + plural, v);
  if (v.empty()) fail(path, "must contain at least one " + singular);
  return v;
}

inline fs::path resolve(const fs::path& base, const std::string& file) {
  const fs::path p(file);
  return p.is_absolute() ? p : base / p;
}

/// A JSON object with a fixed set of allowed keys, and the JSON path used in error messages.
class Obj {
 public:
  Obj(const json& j, std::string path, const std::vector<std::string>& allowed)
      : j_(j), path_(std::move(path)) {
    if (!j.is_object()) expected(path_.empty() ? "top level" : path_, "an object", j);
    for (const auto& item : j.items()) {
      if (std::find(allowed.begin(), allowed.end(), item.key()) != allowed.end()) continue;
      std::string msg = "unknown key " + in_quotes(item.key()) + did_you_mean(item.key(), allowed);
      msg += " (allowed: " + join(allowed) + ")";
      fail(path_, msg);
    }
  }

  const std::string& path() const { return path_; }
  std::string at(const std::string& key) const { return path_.empty() ? key : path_ + "." + key; }
  bool has(const std::string& key) const { return j_.contains(key); }
  const json* find(const std::string& key) const {
    const auto it = j_.find(key);
    return it == j_.end() ? nullptr : &*it;
  }
  const json& req(const std::string& key) const {
    const json* v = find(key);
    if (!v) fail(path_, "missing required field " + in_quotes(key));
    return *v;
  }

  float number(const std::string& key, float def) const {
    const json* v = find(key);
    return v ? as_number(*v, at(key)) : def;
  }
  float positive(const std::string& key) const { return as_positive(req(key), at(key)); }
  Vec3 vec3(const std::string& key) const { return as_vec3(req(key), at(key)); }
  Vec3 position(const std::string& key, const DVec3& origin) const {
    return as_position(req(key), at(key), origin);
  }
  Vec3 vec3(const std::string& key, Vec3 def) const {
    const json* v = find(key);
    return v ? as_vec3(*v, at(key)) : def;
  }
  bool boolean(const std::string& key, bool def) const {
    const json* v = find(key);
    return v ? as_bool(*v, at(key)) : def;
  }
  int integer(const std::string& key, int def, int lo, int hi) const {
    const json* v = find(key);
    return v ? as_int(*v, at(key), lo, hi) : def;
  }
  std::string string(const std::string& key) const { return as_string(req(key), at(key)); }

 private:
  const json& j_;
  std::string path_;
};

inline std::string element(const std::string& array_path, size_t i) {
  return array_path + "[" + std::to_string(i) + "]";
}

// ---- parsing ----------------------------------------------------------------------------------

/// Strict JSON, rejecting duplicate keys within one object (a common copy-paste mistake that the
/// JSON standard leaves undefined).
inline json parse_json(const std::string& text) {
  std::vector<std::set<std::string>> open_objects;
  const json::parser_callback_t reject_duplicates = [&](int, json::parse_event_t event,
                                                        json& parsed) {
    switch (event) {
      case json::parse_event_t::object_start:
        open_objects.emplace_back();
        break;
      case json::parse_event_t::object_end:
        if (!open_objects.empty()) open_objects.pop_back();
        break;
      case json::parse_event_t::key:
        if (!open_objects.empty() && !open_objects.back().insert(parsed.get<std::string>()).second)
          fail("", "duplicate key " + in_quotes(parsed.get<std::string>()));
        break;
      default:
        break;
    }
    return true;
  };
  try {
    return json::parse(text, reject_duplicates, /*allow_exceptions=*/true,
                       /*ignore_comments=*/false);
  } catch (const json::exception& e) {
    // what() = "[json.exception.parse_error.101] parse error at line L, column C: <reason>".
    std::string msg = e.what();
    if (const size_t p = msg.find("] ");
        msg.rfind("[json.exception", 0) == 0 && p != std::string::npos)
      msg = msg.substr(p + 2);
    // A number overflow (1e999) is reported without a position: find the token in the text.
    const size_t q0 = msg.find('\''), q1 = msg.rfind('\'');
    if (msg.find(" at line ") == std::string::npos && q0 != std::string::npos && q1 > q0 + 1) {
      if (const size_t at = text.find(msg.substr(q0 + 1, q1 - q0 - 1)); at != std::string::npos) {
        const size_t line =
            1 + static_cast<size_t>(std::count(text.begin(), text.begin() + at, '\n'));
        const size_t line_start = text.rfind('\n', at);
        const size_t column = line_start == std::string::npos ? at + 1 : at - line_start;
        msg += " at line " + std::to_string(line) + ", column " + std::to_string(column);
      }
    }
    fail("", "invalid JSON: " + msg);
  }
}

/// The largest emission texture (texels): `exact` with a 1024² one takes 1.9 s at 40×30 (2 s for
/// `wedges`), so 2048² bounds those at ~10 s and ~200 MB; sampling methods read one texel per
/// light sample, far fewer.
inline constexpr int64_t kMaxEmissionTexels = int64_t{2048} * 2048;

/// Loads textures once per file (materials and lights may share one).
class TextureCache {
 public:
  TextureCache(Scene& scene, fs::path base) : scene_(scene), base_(std::move(base)) {}

  /// An alpha mask: the image's alpha channel if it has one (grey+alpha, RGBA), else its first
  /// channel; values / 255.
  int alpha(const json& v, const std::string& path) { return load(v, path, false); }
  /// An emission map: RGB, decoded from sRGB to linear.
  int emission(const json& v, const std::string& path) { return load(v, path, true); }

 private:
  int load(const json& v, const std::string& path, bool emission) {
    const fs::path file = resolve(base_, as_string(v, path));
    const std::string key = (emission ? "E:" : "A:") + file.lexically_normal().string();
    if (const auto it = cache_.find(key); it != cache_.end()) return it->second;

    if (const std::string problem = regular_file_problem(file); !problem.empty())
      fail(path, "cannot load texture " + in_quotes(file.string()) + ": " + problem);
    int w = 0, h = 0, n = 0;
    // The size from the header, before decoding: a small PNG may claim 12000² texels, and an
    // emission texture's cost in `exact` and the wedge methods grows with its texels.
    if (emission && stbi_info(file.string().c_str(), &w, &h, &n) &&
        static_cast<int64_t>(w) * h > kMaxEmissionTexels)
      fail(path, "emission texture " + in_quotes(file.string()) + " is " + std::to_string(w) + "x" +
                     std::to_string(h) + ", more than " + std::to_string(kMaxEmissionTexels) +
                     " texels (2048x2048)");
    std::unique_ptr<stbi_uc, void (*)(void*)> pixels(
        stbi_load(file.string().c_str(), &w, &h, &n, emission ? 3 : 0), stbi_image_free);
    if (!pixels) {
      const char* why = stbi_failure_reason();
      fail(path, "cannot load texture " + in_quotes(file.string()) + ": " +
                     (why ? why : "unknown error"));
    }
    if (w <= 0 || h <= 0 || n <= 0) fail(path, "texture " + in_quotes(file.string()) + " is empty");

    Texture t;
    t.name = file.filename().string();
    t.width = w;
    t.height = h;
    t.channels = emission ? 3 : 1;
    const int stride = emission ? 3 : n;
    const int source = emission ? 0 : ((n == 2 || n == 4) ? n - 1 : 0);
    t.texels.resize(static_cast<size_t>(w) * h * t.channels);
    // Row 0 of Texture is v = 0, which is the bottom row of the image (OBJ/OpenGL convention);
    // image files store the top row first.
    for (int y = 0; y < h; ++y) {
      const stbi_uc* row = pixels.get() + static_cast<size_t>(h - 1 - y) * w * stride;
      for (int x = 0; x < w; ++x) {
        float* out = &t.texels[(static_cast<size_t>(y) * w + x) * t.channels];
        for (int c = 0; c < t.channels; ++c) {
          const float value = static_cast<float>(row[x * stride + source + c]) / 255.0f;
          out[c] = emission ? srgb_to_linear(value) : value;
        }
      }
    }
    scene_.textures.push_back(std::move(t));
    const int index = static_cast<int>(scene_.textures.size() - 1);
    cache_.emplace(key, index);
    return index;
  }

  static float srgb_to_linear(float c) {
    return c <= 0.04045f ? c / 12.92f : std::pow((c + 0.055f) / 1.055f, 2.4f);
  }

  Scene& scene_;
  fs::path base_;
  std::map<std::string, int> cache_;
};

}  // namespace penumbra::scene_json
