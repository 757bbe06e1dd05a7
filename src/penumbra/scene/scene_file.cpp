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
#include "penumbra/scene/animation_file.hpp"
#include "penumbra/scene/builtin_scenes.hpp"
#include "penumbra/scene/mesh_loader.hpp"
#include "penumbra/scene/scene_json.hpp"
#include "penumbra/scene/shapes.hpp"

namespace penumbra {

namespace {
using namespace scene_json;

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
  const Obj root(j, "", {"camera", "lights", "materials", "meshes", "ambient", "animation"});
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
  if (const json* v = root.find("animation"))
    scene.animation = parse_animation(*v, scene, textures, base, origin);
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
