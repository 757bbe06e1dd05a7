#include "penumbra/scene/scene_file.hpp"

#include <stb/stb_image.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <fstream>
#include <glm/gtc/matrix_transform.hpp>
#include <limits>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>
#include <string>
#include <system_error>
#include <vector>

#include "penumbra/core/error.hpp"
#include "penumbra/core/files.hpp"
#include "penumbra/core/suggest.hpp"
#include "penumbra/scene/builtin_scenes.hpp"
#include "penumbra/scene/mesh_loader.hpp"
#include "penumbra/scene/shapes.hpp"

namespace penumbra {

namespace {

using json = nlohmann::json;
namespace fs = std::filesystem;

[[noreturn]] void fail(const std::string& where, const std::string& what) {
  throw Error(where.empty() ? what : where + ": " + what);
}

std::string join(const std::vector<std::string>& items, const std::string& sep = ", ") {
  std::string out;
  for (const std::string& s : items) out += (out.empty() ? "" : sep) + s;
  return out;
}

std::string in_quotes(const std::string& s) {
  return quote(s, 200);
}

// ---- typed values -----------------------------------------------------------------------------

/// What a value is, for "expected X (got Y)" messages.
std::string describe(const json& v) {
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

[[noreturn]] void expected(const std::string& path, const std::string& what, const json& got) {
  fail(path, "expected " + what + " (got " + describe(got) + ")");
}

double as_double(const json& v, const std::string& path, double limit) {
  if (!v.is_number()) expected(path, "a number", v);
  const double d = v.get<double>();
  if (!std::isfinite(d)) fail(path, "must be a finite number");
  if (std::fabs(d) > limit) fail(path, "number out of range");
  return d;
}

float as_number(const json& v, const std::string& path) {
  return static_cast<float>(
      as_double(v, path, static_cast<double>(std::numeric_limits<float>::max())));
}

/// Positions are read in double and moved by −origin before they are rounded to float, so a scene
/// far from the world origin keeps the precision it would have next to it (recentre_scene).
/// Beyond 1e15 even double cannot place a detail of the scene's own size.
constexpr double kMaxPosition = 1e15;

double as_coordinate(const json& v, const std::string& path) {
  if (v.is_number() && std::isfinite(v.get<double>()) && std::fabs(v.get<double>()) > kMaxPosition)
    fail(path, "beyond 1e15 in magnitude (unsupported range)");
  return as_double(v, path, kMaxPosition);
}

Vec3 as_position(const json& v, const std::string& path, const DVec3& origin) {
  if (!v.is_array() || v.size() != 3) expected(path, "an array of 3 numbers", v);
  Vec3 out;
  for (int i = 0; i < 3; ++i)
    out[i] =
        static_cast<float>(as_coordinate(v[i], path + "[" + std::to_string(i) + "]") - origin[i]);
  return out;
}

float as_positive(const json& v, const std::string& path) {
  const float x = as_number(v, path);
  if (!(x > 0.0f)) fail(path, "must be positive");
  return x;
}

int as_int(const json& v, const std::string& path, int lo, int hi) {
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

bool as_bool(const json& v, const std::string& path) {
  if (!v.is_boolean()) expected(path, "true or false", v);
  return v.get<bool>();
}

std::string as_string(const json& v, const std::string& path) {
  if (!v.is_string()) expected(path, "a string", v);
  std::string s = v.get<std::string>();
  if (s.empty()) fail(path, "must not be empty");
  // A path would be cut at the NUL by the file system calls, and load another file.
  if (s.find('\0') != std::string::npos) fail(path, "must not contain a NUL character (\\u0000)");
  return s;
}

Vec3 as_vec3(const json& v, const std::string& path) {
  if (!v.is_array() || v.size() != 3) expected(path, "an array of 3 numbers", v);
  Vec3 out;
  for (int i = 0; i < 3; ++i) out[i] = as_number(v[i], path + "[" + std::to_string(i) + "]");
  return out;
}

/// A non-negative colour: one number (grey) or [r, g, b].
Vec3 as_color(const json& v, const std::string& path, bool allow_scalar) {
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
const json& as_array(const json& v, const std::string& path, const std::string& plural,
                     const std::string& singular) {
  if (!v.is_array()) expected(path, "an array of " + plural, v);
  if (v.empty()) fail(path, "must contain at least one " + singular);
  return v;
}

fs::path resolve(const fs::path& base, const std::string& file) {
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

std::string element(const std::string& array_path, size_t i) {
  return array_path + "[" + std::to_string(i) + "]";
}

// ---- parsing ----------------------------------------------------------------------------------

/// Strict JSON, rejecting duplicate keys within one object (a common copy-paste mistake that the
/// JSON standard leaves undefined).
json parse_json(const std::string& text) {
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
constexpr int64_t kMaxEmissionTexels = int64_t{2048} * 2048;

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

Camera parse_camera(const json& j, const DVec3& origin) {
  const Obj o(j, "camera", {"position", "target", "up", "fov_deg", "width", "height"});
  Camera c;
  c.position = o.position("position", origin);
  c.target = o.position("target", origin);
  c.up = o.vec3("up", c.up);
  c.vfov_deg = o.number("fov_deg", c.vfov_deg);
  if (!(c.vfov_deg > 0.0f && c.vfov_deg < 180.0f))
    fail(o.at("fov_deg"), "must be in (0, 180) degrees");
  c.width = o.integer("width", c.width, 1, 16384);
  c.height = o.integer("height", c.height, 1, 16384);
  if (c.target == c.position) fail(o.at("target"), "equals camera.position");
  if (sine_between(DVec3(c.target) - DVec3(c.position), DVec3(c.up)) <= kParallelSine)
    fail(o.at("up"), "is zero or parallel to the view direction");
  return c;
}

std::vector<Material> parse_materials(const json& j, TextureCache& textures) {
  std::vector<Material> out;
  std::set<std::string> names;
  const json& array = as_array(j, "materials", "materials", "material");
  for (size_t i = 0; i < array.size(); ++i) {
    const Obj o(array[i], element("materials", i),
                {"name", "albedo", "alpha_texture", "transmittance"});
    Material m;
    m.name = o.string("name");
    if (!names.insert(m.name).second)
      fail(o.at("name"), "duplicate material name " + in_quotes(m.name));
    if (const json* v = o.find("albedo")) {
      m.albedo = as_color(*v, o.at("albedo"), false);
      if (m.albedo.x > 1.0f || m.albedo.y > 1.0f || m.albedo.z > 1.0f)
        fail(o.at("albedo"), "components must be in [0, 1]");
    }
    if (const json* v = o.find("alpha_texture"))
      m.alpha_texture = textures.alpha(*v, o.at("alpha_texture"));
    m.transmittance = o.number("transmittance", 0.0f);
    if (!(m.transmittance >= 0.0f && m.transmittance < 1.0f))
      fail(o.at("transmittance"), "must be in [0, 1) (0 = opaque)");
    out.push_back(std::move(m));
  }
  return out;
}

/// translate · rotate · scale, or an explicit matrix; world = M · local.
Mat4 parse_transform(const json& j, const std::string& path, const DVec3& origin) {
  const Obj o(j, path, {"translate", "rotate_deg", "scale", "matrix"});
  Mat4 m(1.0f);
  if (const json* v = o.find("matrix")) {
    if (o.has("translate") || o.has("rotate_deg") || o.has("scale"))
      fail(path, "give either 'matrix' or translate/rotate_deg/scale, not both");
    const std::string mpath = o.at("matrix");
    if (!v->is_array() || v->size() != 16)
      expected(mpath, "an array of 16 numbers (row-major 4x4)", *v);
    for (int r = 0; r < 4; ++r)
      for (int c = 0; c < 4; ++c)
        m[c][r] = c == 3 && r < 3
                      ? static_cast<float>(
                            as_coordinate((*v)[r * 4 + c], element(mpath, r * 4 + c)) - origin[r])
                      : as_number((*v)[r * 4 + c], element(mpath, r * 4 + c));
    if (m[0][3] != 0.0f || m[1][3] != 0.0f || m[2][3] != 0.0f || m[3][3] != 1.0f)
      fail(mpath, "the last row must be [0, 0, 0, 1] (affine transforms only)");
  } else {
    const Vec3 t = o.has("translate") ? o.position("translate", origin) : Vec3(-origin);
    const Vec3 r = glm::radians(o.vec3("rotate_deg", Vec3(0.0f)));
    Vec3 s(1.0f);
    if (const json* v = o.find("scale")) {
      if (v->is_number()) {
        s = Vec3(as_number(*v, o.at("scale")));
      } else if (v->is_array()) {
        s = as_vec3(*v, o.at("scale"));
      } else {
        expected(o.at("scale"), "a number or an array of 3 numbers", *v);
      }
      if (s.x == 0.0f || s.y == 0.0f || s.z == 0.0f) fail(o.at("scale"), "must be nonzero");
    }
    // XYZ Euler: rotate about the world x axis first, then y, then z.
    m = glm::translate(Mat4(1.0f), t);
    m = glm::rotate(m, r.z, Vec3(0, 0, 1));
    m = glm::rotate(m, r.y, Vec3(0, 1, 0));
    m = glm::rotate(m, r.x, Vec3(1, 0, 0));
    m = glm::scale(m, s);
  }
  // Singular relative to the columns' lengths, in double: a uniform scale of 1e-4 (det 1e-12) is
  // a legitimate transform, a flattening one is not, whatever the scale.
  const glm::dmat3 linear(glm::mat3{m});
  const double volume_bound =
      glm::length(linear[0]) * glm::length(linear[1]) * glm::length(linear[2]);
  const double det = glm::determinant(linear);
  if (!std::isfinite(det) || !(std::fabs(det) > 1e-9 * volume_bound))
    fail(path, "is singular (zero volume)");
  return m;
}

void apply_transform(Mesh& mesh, const Mat4& m, const std::string& path) {
  transform_mesh(mesh, m);
  for (const Vec3& p : mesh.positions)
    if (!is_finite(p)) fail(path, "produces non-finite vertex positions");
}

/// Mesh files already read, by path (a scene far from the origin is parsed twice).
using LoadedMeshes = std::map<fs::path, Mesh>;

Mesh parse_mesh(const json& j, size_t index, const std::map<std::string, int>& materials,
                const fs::path& base, const DVec3& origin, LoadedMeshes& loaded) {
  const std::string path = element("meshes", index);
  if (!j.is_object()) expected(path, "an object", j);
  std::vector<std::string> allowed = {"name",      "file",          "shape",           "material",
                                      "transform", "casts_shadows", "receives_shadows"};
  std::string shape;
  if (j.contains("file") && j.contains("shape"))
    fail(path, "give either 'file' or 'shape', not both");
  if (j.contains("shape")) {
    shape = as_string(j["shape"], path + ".shape");
    if (shape == "quad") {
      allowed.insert(allowed.end(), {"center", "edge_u", "edge_v"});
    } else if (shape == "box") {
      allowed.insert(allowed.end(), {"center", "half_extent"});
    } else if (shape == "sphere") {
      allowed.insert(allowed.end(), {"center", "radius", "rings", "segments"});
    } else {
      fail(path + ".shape",
           "unknown shape " + in_quotes(shape) + " (expected quad, box or sphere)");
    }
  } else if (!j.contains("file")) {
    fail(path, "missing required field 'file' or 'shape'");
  }
  const Obj o(j, path, allowed);

  // A transform carries the mesh to its place (its translation is moved by −origin); without one
  // the shape's centre or the file's vertices are.
  const json* transform = o.find("transform");
  const DVec3 local_origin = transform ? DVec3(0.0) : origin;
  Mesh mesh;
  if (shape.empty()) {
    const fs::path file = resolve(base, o.string("file"));
    try {
      auto it = loaded.find(file);
      if (it == loaded.end()) it = loaded.emplace(file, load_mesh_file(file)).first;
      mesh = it->second;
    } catch (const Error& e) {
      fail(o.at("file"), e.what());
    }
    mesh.name = file.stem().string();
    mesh.source_file = fs::absolute(file).lexically_normal().string();
  } else if (shape == "quad") {
    const Vec3 center = o.position("center", local_origin), eu = o.vec3("edge_u"),
               ev = o.vec3("edge_v");
    if (!(sine_between(DVec3(eu), DVec3(ev)) > kParallelSine))
      fail(path, "edge_u and edge_v span zero area");
    mesh = make_quad(center, eu, ev);
  } else if (shape == "box") {
    const Vec3 center = o.position("center", local_origin), half = o.vec3("half_extent");
    if (!(half.x > 0.0f && half.y > 0.0f && half.z > 0.0f))
      fail(o.at("half_extent"), "components must be positive");
    mesh = make_box(center, half);
  } else {
    const Vec3 center = o.position("center", local_origin);
    const float radius = o.positive("radius");
    const int rings = o.integer("rings", 16, 2, 1024);
    const int segments = o.integer("segments", 32, 3, 2048);
    mesh = make_sphere(center, radius, rings, segments);
  }
  mesh.name = o.has("name") ? o.string("name") : shape.empty() ? mesh.name : shape;

  const std::string material = o.string("material");
  const auto it = materials.find(material);
  if (it == materials.end()) {
    std::vector<std::string> known;
    for (const auto& [name, i] : materials) known.push_back(name);
    fail(o.at("material"),
         "unknown material " + in_quotes(material) + " (defined: " + join(known) + ")");
  }
  mesh.material = it->second;
  mesh.casts_shadows = o.boolean("casts_shadows", true);
  mesh.receives_shadows = o.boolean("receives_shadows", true);
  if (transform || (shape.empty() && origin != DVec3(0.0))) {
    const Mat4 m = transform ? parse_transform(*transform, o.at("transform"), origin)
                             : glm::translate(Mat4(1.0f), Vec3(-origin));
    apply_transform(mesh, m, o.at("transform"));
    if (!mesh.source_file.empty()) mesh.source_transform = m;
  }
  return mesh;
}

Light parse_light(const json& j, size_t index, TextureCache& textures, const DVec3& origin) {
  const std::string path = element("lights", index);
  if (!j.is_object()) expected(path, "an object", j);
  if (!j.contains("type"))
    fail(path, "missing required field 'type' (rect, disk, sphere or point)");
  const std::string type = as_string(j["type"], path + ".type");
  std::vector<std::string> allowed = {"type", "name", "center", "radiance"};
  Light l;
  if (type == "rect") {
    l.shape = LightShape::rect;
    allowed.insert(allowed.end(), {"edge_u", "edge_v", "two_sided", "emission_texture"});
  } else if (type == "disk") {
    l.shape = LightShape::disk;
    allowed.insert(allowed.end(), {"normal", "radius"});
  } else if (type == "sphere") {
    l.shape = LightShape::sphere;
    allowed.insert(allowed.end(), {"radius"});
  } else if (type == "point") {
    l.shape = LightShape::point;
  } else {
    fail(path + ".type",
         "unknown light type " + in_quotes(type) + " (expected rect, disk, sphere or point)");
  }
  const Obj o(j, path, allowed);
  l.name = o.has("name") ? o.string("name") : path;
  l.center = o.position("center", origin);
  l.radiance = as_color(o.req("radiance"), o.at("radiance"), true);
  switch (l.shape) {
    case LightShape::rect:
      l.edge_u = o.vec3("edge_u");
      l.edge_v = o.vec3("edge_v");
      if (!(sine_between(DVec3(l.edge_u), DVec3(l.edge_v)) > kParallelSine))
        fail(path, "edge_u and edge_v span zero area");
      l.two_sided = o.boolean("two_sided", false);
      if (const json* v = o.find("emission_texture"))
        l.emission_texture = textures.emission(*v, o.at("emission_texture"));
      break;
    case LightShape::disk: {
      const Vec3 n = o.vec3("normal");
      if (!(glm::length(DVec3(n)) > 0.0)) fail(o.at("normal"), "must be nonzero");
      l.normal = Vec3(glm::normalize(DVec3(n)));  // in double: a tiny normal does not underflow
      l.radius = o.positive("radius");
      break;
    }
    case LightShape::sphere:
      l.radius = o.positive("radius");
      break;
    case LightShape::point:
      break;
  }
  return l;
}

/// The scene with every position moved by −origin (in double, before rounding to float).
Scene parse_scene(const json& j, const fs::path& base, const DVec3& origin, LoadedMeshes& loaded) {
  const Obj root(j, "", {"camera", "lights", "materials", "meshes", "ambient"});
  Scene scene;
  TextureCache textures(scene, base);
  scene.camera = parse_camera(root.req("camera"), origin);
  scene.origin = origin;
  if (const json* v = root.find("ambient")) scene.ambient = as_color(*v, "ambient", false);

  scene.materials = parse_materials(root.req("materials"), textures);
  std::map<std::string, int> material_index;
  for (size_t i = 0; i < scene.materials.size(); ++i)
    material_index.emplace(scene.materials[i].name, static_cast<int>(i));

  const json& meshes = as_array(root.req("meshes"), "meshes", "meshes", "mesh");
  for (size_t i = 0; i < meshes.size(); ++i)
    scene.meshes.push_back(parse_mesh(meshes[i], i, material_index, base, origin, loaded));

  const json& lights = as_array(root.req("lights"), "lights", "lights", "light");
  for (size_t i = 0; i < lights.size(); ++i)
    scene.lights.push_back(parse_light(lights[i], i, textures, origin));
  return scene;
}

}  // namespace

Scene load_scene_file(const fs::path& path) {
  try {
    if (const std::string problem = regular_file_problem(path); !problem.empty()) fail("", problem);
    std::ifstream in(path, std::ios::binary);
    if (!in) fail("", "cannot open the file");
    std::ostringstream text;
    text << in.rdbuf();
    if (in.bad()) fail("", "cannot read the file");
    // JSON text holds no raw NUL (nlohmann stops at one and accepts what precedes it).
    if (const size_t nul = text.view().find('\0'); nul != std::string::npos)
      fail("", "a NUL byte at offset " + std::to_string(nul) + " (not JSON text)");

    const json j = parse_json(text.str());
    fs::path base = path.parent_path();
    if (base.empty()) base = ".";
    // Parsed once where it lies; a scene far from the origin is parsed again moved next to it,
    // its positions subtracted in double (the mesh files are read once).
    LoadedMeshes loaded;
    Scene scene = parse_scene(j, base, DVec3(0.0), loaded);
    if (const DVec3 offset = recentring_offset(scene); offset != DVec3(0.0)) {
      scene = Scene{};
      scene = parse_scene(j, base, offset, loaded);
    }
    scene.name = path.stem().string();
    validate_scene(scene);
    return scene;
  } catch (const Error& e) {
    throw Error("scene file " + quote(path.string(), 200) + ": " + e.what());
  } catch (const std::bad_alloc&) {
    throw Error("scene file " + quote(path.string(), 200) + ": out of memory");
  }
}

void check_scene_name(std::string_view name_or_path) {
  if (is_builtin_scene(name_or_path)) return;
  const fs::path path{std::string(name_or_path)};
  std::error_code ec;
  if (fs::exists(path, ec)) {
    const std::string what = is_model_path(path) ? "cannot load mesh" : "scene file";
    require_regular_file(path, what);
    return;
  }
  std::vector<std::string> names;
  for (const BuiltinSceneInfo& info : builtin_scenes()) names.push_back(info.name);
  throw Error("unknown scene " + quote(name_or_path, 200) + did_you_mean(name_or_path, names) +
              ": not a built-in scene (" + join(names) + ") nor an existing scene or model file");
}

Scene load_scene(std::string_view name_or_path, const ModelFraming& framing) {
  if (is_builtin_scene(name_or_path)) return make_builtin_scene(name_or_path);
  check_scene_name(name_or_path);
  const fs::path path{std::string(name_or_path)};
  return is_model_path(path) ? load_model_scene(path, framing) : load_scene_file(path);
}

}  // namespace penumbra
