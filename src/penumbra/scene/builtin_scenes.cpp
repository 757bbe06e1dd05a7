#include "penumbra/scene/builtin_scenes.hpp"

#include <algorithm>
#include <cmath>
#include <functional>
#include <glm/gtc/matrix_transform.hpp>

#include "penumbra/core/error.hpp"
#include "penumbra/scene/animated_scenes.hpp"
#include "penumbra/scene/mesh_loader.hpp"
#include "penumbra/scene/model_paths.hpp"
#include "penumbra/scene/model_scene.hpp"
#include "penumbra/scene/scene_classes.hpp"
#include "penumbra/scene/scene_parts.hpp"
#include "penumbra/scene/shapes.hpp"

namespace penumbra {

namespace {

/// A fence/lattice alpha mask: vertical slats and two rails, 64×64 texels.
int add_fence_texture(Scene& s) {
  Texture t;
  t.name = "fence_alpha";
  t.width = t.height = 64;
  t.channels = 1;
  t.texels.resize(64 * 64);
  for (int y = 0; y < 64; ++y) {
    for (int x = 0; x < 64; ++x) {
      const bool slat = (x % 8) < 4;
      const bool rail = (y >= 8 && y < 14) || (y >= 50 && y < 56);
      t.texels[y * 64 + x] = (slat || rail) ? 1.0f : 0.0f;
    }
  }
  s.textures.push_back(std::move(t));
  return static_cast<int>(s.textures.size() - 1);
}

Scene quad_scene() {
  Scene s;
  s.name = "quad";
  add_ground(s);
  const QuadSceneGeometry g = kQuadScene;
  const int mat = add_material(s, "occluder", Vec3(0.6f, 0.3f, 0.2f));
  add_mesh(s,
           make_quad(Vec3(0, g.occluder_height, 0), Vec3(0, 0, g.occluder_side),
                     Vec3(g.occluder_side, 0, 0)),
           "occluder", mat);
  s.lights.push_back(square_light(Vec3(0, g.light_height, 0), g.light_side, 4.0f));
  s.camera.position = Vec3(0.0f, 2.6f, 3.2f);
  s.camera.target = Vec3(0.0f, 0.0f, 0.2f);
  return s;
}

Scene spheres_scene() {
  Scene s;
  s.name = "spheres";
  add_ground(s);
  const int mat = add_material(s, "spheres", Vec3(0.3f, 0.5f, 0.8f));
  Mesh all;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      for (int k = 0; k < 3; ++k) {
        const Vec3 c(0.4f * static_cast<float>(i - 1), 0.6f + 0.4f * static_cast<float>(j),
                     0.4f * static_cast<float>(k - 1));
        append_mesh(all, make_sphere(c, 0.15f, 12, 24));
      }
  add_mesh(s, std::move(all), "spheres", mat);
  s.lights.push_back(square_light(Vec3(0.3f, 3.0f, 0.2f), 1.0f, 4.0f));
  s.camera.position = Vec3(2.4f, 2.6f, 3.0f);
  s.camera.target = Vec3(0.0f, 0.5f, 0.0f);
  return s;
}

Scene fence_scene() {
  Scene s;
  s.name = "fence";
  add_ground(s);
  const int tex = add_fence_texture(s);
  const int mat = add_material(s, "fence", Vec3(0.7f, 0.55f, 0.35f), tex);
  add_mesh(s, make_quad(Vec3(0, 1.0f, 0), Vec3(0, 0, 1.6f), Vec3(1.6f, 0, 0)), "fence", mat);
  s.lights.push_back(square_light(Vec3(0, 3.0f, 0), 0.4f, 8.0f));
  s.camera.position = Vec3(0.0f, 2.8f, 3.0f);
  s.camera.target = Vec3(0.0f, 0.2f, 0.0f);
  return s;
}

Scene default_scene() {
  Scene s;
  s.name = "default";
  add_ground(s);
  const int red = add_material(s, "box", Vec3(0.7f, 0.25f, 0.2f));
  const int blue = add_material(s, "sphere", Vec3(0.25f, 0.4f, 0.75f));
  const int fence_mat = add_material(s, "fence", Vec3(0.7f, 0.6f, 0.4f), add_fence_texture(s));
  add_mesh(s, make_box(Vec3(-0.6f, 0.35f, 0.1f), Vec3(0.25f, 0.35f, 0.25f)), "box", red);
  add_mesh(s, make_sphere(Vec3(0.45f, 0.55f, -0.2f), 0.3f, 16, 32), "sphere", blue);
  add_mesh(s, make_quad(Vec3(0.2f, 1.2f, 0.7f), Vec3(0, 0, 0.8f), Vec3(0.8f, 0, 0)), "fence",
           fence_mat);
  s.lights.push_back(square_light(Vec3(0.1f, 3.0f, 0.2f), 0.8f, 5.0f));
  s.camera.position = Vec3(2.2f, 2.4f, 3.2f);
  s.camera.target = Vec3(0.0f, 0.4f, 0.1f);
  return s;
}

}  // namespace

Mat4 model_framing_matrix(const Mesh& model, ModelUp up) {
  // Z-up to Y-up: (x, y, z) -> (x, z, -y), a quarter turn about x (exact in floats).
  const Mat4 turn = up == ModelUp::z ? Mat4(Vec4(1, 0, 0, 0), Vec4(0, 0, -1, 0), Vec4(0, 1, 0, 0),
                                            Vec4(0, 0, 0, 1))
                                     : Mat4(1.0f);
  Bounds3 b;
  for (const Vec3& p : model.positions) b.extend(Vec3(turn * Vec4(p, 1.0f)));
  const float scale = 1.0f / b.diagonal();
  const Vec3 offset(-b.center().x, -b.lo.y, -b.center().z);
  Mat4 m = glm::scale(Mat4(1.0f), Vec3(scale)) * glm::translate(Mat4(1.0f), offset) * turn;
  return m;
}

/// The benchmark scene layout: model scaled to a bounding-box diagonal of 1, resting on
/// the 10×10 ground at y = 0, a square light (side 0.5 by default) parallel to the ground 2.0
/// above the model's centre, camera at (1.5, 1.2, 1.5) looking at the model's centre, 45°
/// vertical fov.
Scene frame_model(Mesh model, const std::string& name, const ModelFraming& framing,
                  const std::filesystem::path& source) {
  if (model.positions.empty() || !(model.bounds().diagonal() > 0.0f))
    throw Error("model '" + name + "' has no extent (all its vertices coincide)");
  if (!(framing.light_size > 0.0f) || !std::isfinite(framing.light_size))
    throw Error("--light-size must be a positive number");
  if (!(framing.light_height > 0.0f) || !std::isfinite(framing.light_height))
    throw Error("--light-height must be a positive number");
  const Mat4 m =
      model_framing_matrix(model, framing.up == ModelUp::automatic ? ModelUp::y : framing.up);
  transform_mesh(model, m);
  if (!source.empty()) {
    model.source_file = std::filesystem::absolute(source).lexically_normal().string();
    model.source_transform = m;
  }
  const Vec3 model_center = model.bounds().center();

  Scene s;
  s.name = name;
  add_ground(s);
  const int mat = add_material(s, name, Vec3(0.8f, 0.75f, 0.65f));
  add_mesh(s, std::move(model), name, mat);
  // The same irradiance under the light whatever its size: power scales with 1 / area.
  const float power = 16.0f * (0.5f * 0.5f) / (framing.light_size * framing.light_size);
  s.lights.push_back(
      square_light(model_center + Vec3(0, framing.light_height, 0), framing.light_size, power));
  s.camera.position = Vec3(1.5f, 1.2f, 1.5f);
  s.camera.target = model_center;
  s.camera.vfov_deg = 45.0f;
  if (framing.fit_camera) {
    const float radius = 0.5f;  // of the bounding sphere: the diagonal is 1
    const float distance = radius / std::sin(glm::radians(0.5f * s.camera.vfov_deg));
    s.camera.position =
        model_center + distance * glm::normalize(Vec3(1.5f, 1.2f, 1.5f) - model_center);
  }
  return s;
}

namespace {

Scene model_scene(const std::string& name, const std::string& file_name) {
  const auto path = find_model(file_name);
  if (!path) {
    throw Error("scene '" + name + "' needs " + file_name + ", which is not in " +
                models_dir().string() + ": run scripts/fetch-models.sh (or set PENUMBRA_MODELS)");
  }
  ModelFraming benchmark_layout;
  benchmark_layout.fit_camera = false;
  return frame_model(load_mesh_file(*path), name, benchmark_layout, *path);
}

std::string model_origin(const std::string& file_name) {
  if (const auto path = find_model(file_name)) return "CGAL model " + path->string();
  return "needs " + file_name + " (not in " + models_dir().string() +
         "): run scripts/fetch-models.sh";
}

std::string seeded_origin() {
  return "procedural, PCG32 seed " + std::to_string(kSceneClassSeed);
}

struct Entry {
  BuiltinSceneInfo info;
  std::function<Scene()> make;
  std::function<std::string()> origin = [] { return std::string("procedural"); };
};

const std::vector<Entry>& entries() {
  static const std::vector<Entry> list = {
      {{"quad",
        "square occluder parallel to a square light over a ground plane (closed-form penumbra)",
        false},
       quad_scene},
      {{"spheres", "3x3x3 grid of spheres over a plane: overlapping penumbrae", false},
       spheres_scene},
      {{"fence", "alpha-textured fence quad over a plane (perforated occluder)", false},
       fence_scene},
      {{"default", "box, sphere and fence panel over a plane: the main job's scene", false},
       default_scene},
      {{"nest",
        "20k thin disconnected twigs (120k triangles) in a bowl over a plane: fragmented geometry",
        false},
       [] { return make_nest_scene(); },
       seeded_origin},
      {{"garden",
        "400 plants, 102k alpha-textured leaf cards (207k triangles) over a plane: foliage", false},
       [] { return make_garden_scene(); },
       seeded_origin},
      {{"herd",
        "six dense models side by side (CGAL models, 364k triangles; procedural shapes, 344k, "
        "when not fetched)",
        false},
       [] { return make_herd_scene(); },
       herd_origin},
      {{"bunny_orbit",
        "animated, 4 s: the square light circles the bunny and grows (a procedural bumpy ball "
        "when the bunny is not fetched)",
        false},
       make_bunny_orbit_scene,
       [] {
         return find_model("bunny00.off") ? model_origin("bunny00.off")
                                          : std::string(
                                                "procedural bumpy ball (bunny00.off not "
                                                "fetched: run scripts/fetch-models.sh)");
       }},
      {{"fence_spin", "animated, 3 s: the alpha-textured fence turning under the light (60 deg/s)",
        false},
       make_fence_spin_scene},
      {{"flag",
        "animated, 2 s: a waving cloth (3k triangles, a vertex clip) on a pole, shadowing itself",
        false},
       make_flag_scene},
      {{"marquee",
        "animated, 2 s: a video-textured light (8 frames of moving stripes at 12 fps) over boxes",
        false},
       make_marquee_scene},
      {{"bunny", "Stanford bunny (CGAL data, 75k triangles), the benchmark scene", true},
       [] { return model_scene("bunny", "bunny00.off"); },
       [] { return model_origin("bunny00.off"); }},
      {{"dragon", "Chinese dragon (CGAL data, 20k triangles), same layout as bunny", true},
       [] { return model_scene("dragon", "ChineseDragon-10kv.off"); },
       [] { return model_origin("ChineseDragon-10kv.off"); }},
      {{"armadillo", "Armadillo (CGAL data, 52k triangles, closed), same layout as bunny", true},
       [] { return model_scene("armadillo", "armadillo.off"); },
       [] { return model_origin("armadillo.off"); }},
      {{"elephant", "refined elephant (CGAL data, 89k triangles, closed), same layout as bunny",
        true},
       [] { return model_scene("elephant", "refined_elephant.off"); },
       [] { return model_origin("refined_elephant.off"); }},
  };
  return list;
}

}  // namespace

const std::vector<BuiltinSceneInfo>& builtin_scenes() {
  static const std::vector<BuiltinSceneInfo> infos = [] {
    std::vector<BuiltinSceneInfo> v;
    for (const Entry& e : entries()) v.push_back(e.info);
    return v;
  }();
  return infos;
}

bool is_builtin_scene(std::string_view name) {
  return std::any_of(entries().begin(), entries().end(),
                     [&](const Entry& e) { return e.info.name == name; });
}

std::string builtin_scene_origin(std::string_view name) {
  for (const Entry& e : entries())
    if (e.info.name == name) return e.origin();
  return {};
}

Scene make_builtin_scene(std::string_view name) {
  for (const Entry& e : entries()) {
    if (e.info.name == name) {
      Scene s = e.make();
      validate_scene(s);
      return s;
    }
  }
  std::string known;
  for (const Entry& e : entries()) known += (known.empty() ? "" : ", ") + e.info.name;
  throw Error("unknown built-in scene " + quote(name) + " (known: " + known + ")");
}

double quad_scene_visible_fraction(double x, double y, double z) {
  const QuadSceneGeometry g = kQuadScene;
  // A point p at height y sees occluder coordinate o on the light plane at p + (o - p)(H − y)/(h −
  // y).
  const double ratio = (g.light_height - y) / (g.occluder_height - y);
  const auto covered_1d = [&](double p) {
    const double half_o = 0.5 * g.occluder_side, half_l = 0.5 * g.light_side;
    const double lo = p + (-half_o - p) * ratio, hi = p + (half_o - p) * ratio;
    const double overlap = std::min(hi, half_l) - std::max(lo, -half_l);
    return std::clamp(overlap / g.light_side, 0.0, 1.0);
  };
  return 1.0 - covered_1d(x) * covered_1d(z);
}

}  // namespace penumbra
