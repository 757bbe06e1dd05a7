// `herd`: several dense closed models side by side — the fetched CGAL models, or procedural
// stand-ins of the same density when they are not fetched, so the scene always loads.
#include <algorithm>
#include <array>
#include <cmath>
#include <glm/gtc/matrix_transform.hpp>
#include <optional>

#include "penumbra/scene/mesh_loader.hpp"
#include "penumbra/scene/model_paths.hpp"
#include "penumbra/scene/model_scene.hpp"
#include "penumbra/scene/procedural.hpp"
#include "penumbra/scene/scene_classes.hpp"
#include "penumbra/scene/scene_parts.hpp"
#include "penumbra/scene/shapes.hpp"

namespace penumbra {

namespace {

struct HerdModel {
  const char* name;
  const char* file;
  Vec3 albedo;
};

const std::array<HerdModel, 4> kModels = {{
    {"bunny", "bunny00.off", Vec3(0.8f, 0.75f, 0.65f)},
    {"dragon", "ChineseDragon-10kv.off", Vec3(0.55f, 0.7f, 0.45f)},
    {"armadillo", "armadillo.off", Vec3(0.75f, 0.55f, 0.4f)},
    {"elephant", "refined_elephant.off", Vec3(0.6f, 0.6f, 0.7f)},
}};
/// Which model stands in each of the six places (two rows of three), front row first: 364k
/// triangles with the CGAL models.
constexpr std::array<int, 6> kLayout = {0, 1, 2, 3, 0, 2};
constexpr float kSpacingX = 0.85f, kSpacingZ = 0.9f;
constexpr float kModelDiagonal = 0.8f;

/// Pushes each vertex along its unit normal by a few seeded waves over the normal's direction
/// (amplitude in units of `scale`), then drops the normals: flat shaded, like the fetched models.
void add_bumps(Pcg32& rng, Mesh& m, float scale) {
  struct Wave {
    Vec3 direction;
    float frequency, phase, amplitude;
  };
  std::array<Wave, 4> waves{};
  for (Wave& w : waves) {
    w.direction = random_direction(rng);
    w.frequency = uniform_in(rng, 3.0f, 9.0f);
    w.phase = uniform_in(rng, 0.0f, 2.0f * static_cast<float>(kPi));
    w.amplitude = uniform_in(rng, 0.02f, 0.05f) * scale;
  }
  for (size_t i = 0; i < m.positions.size(); ++i) {
    float offset = 0.0f;
    for (const Wave& w : waves)
      offset += w.amplitude * std::sin(w.frequency * glm::dot(m.normals[i], w.direction) + w.phase);
    m.positions[i] += offset * m.normals[i];
  }
  m.normals.clear();
}

/// The procedural stand-in for place `i`: a bumpy sphere or a bumpy, tilted torus of about
/// segments² triangles (57k at 240: a dense closed 2-manifold, like the models).
Mesh procedural_model(Pcg32& rng, int i, int segments) {
  if (i % 2 == 0) {
    Mesh m = make_sphere(Vec3(0.0f), 1.0f, segments / 2, segments);
    add_bumps(rng, m, 1.0f);
    return m;
  }
  Mesh m = make_torus(Vec3(0.0f), 1.0f, 0.4f, segments, segments / 2);
  add_bumps(rng, m, 0.4f);
  const float tilt = uniform_in(rng, 0.4f, 1.1f);  // radians: a ring leaning over
  transform_mesh(m, glm::rotate(Mat4(1.0f), tilt, Vec3(1, 0, 0)));
  return m;
}

/// The CGAL models, each loaded once; nothing when any is missing.
std::optional<std::array<Mesh, 4>> load_models() {
  std::array<Mesh, 4> meshes;
  for (size_t k = 0; k < kModels.size(); ++k) {
    const auto path = find_model(kModels[k].file);
    if (!path) return std::nullopt;
    meshes[k] = load_mesh_file(*path);
  }
  return meshes;
}

/// Frames `m` like the model scenes (diagonal 1, standing on y = 0), then scales it to
/// kModelDiagonal, turns it by `yaw` about the vertical and moves it to `place`.
void place_model(Mesh& m, const Vec3& place, float yaw) {
  const Mat4 instance =
      glm::translate(Mat4(1.0f), place) * glm::rotate(Mat4(1.0f), yaw, Vec3(0, 1, 0)) *
      glm::scale(Mat4(1.0f), Vec3(kModelDiagonal)) * model_framing_matrix(m, ModelUp::y);
  transform_mesh(m, instance);
  // The framing puts the lowest point at y = 0 before the turn, which rounding may undo by 1e-8.
  float lowest = kInfinity;
  for (const Vec3& p : m.positions) lowest = std::min(lowest, p.y);
  if (lowest < 0.0f)
    for (Vec3& p : m.positions) p.y -= lowest;
}

}  // namespace

bool herd_models_fetched() {
  for (const HerdModel& m : kModels)
    if (!find_model(m.file)) return false;
  return true;
}

std::string herd_origin() {
  std::string files;
  for (const HerdModel& m : kModels) files += (files.empty() ? "" : ", ") + std::string(m.file);
  if (herd_models_fetched()) return "CGAL models (" + files + ") from " + models_dir().string();
  return "procedural stand-ins (bumpy spheres and tori): the CGAL models (" + files +
         ") are not all in " + models_dir().string() + "; run scripts/fetch-models.sh";
}

Scene make_herd_scene(uint64_t seed, HerdSource source, int shape_segments) {
  Pcg32 rng(seed, /*stream=*/3);
  std::optional<std::array<Mesh, 4>> models;
  if (source == HerdSource::automatic) models = load_models();

  Scene s;
  s.name = "herd";
  add_ground(s);
  std::array<int, kModels.size()> materials{};
  if (models) {
    for (size_t k = 0; k < kModels.size(); ++k)
      materials[k] = add_material(s, kModels[k].name, kModels[k].albedo);
  } else {
    materials[0] = add_material(s, "blob", Vec3(0.8f, 0.75f, 0.65f));
    materials[1] = add_material(s, "torus", Vec3(0.6f, 0.6f, 0.7f));
  }
  for (int i = 0; i < static_cast<int>(kLayout.size()); ++i) {
    const Vec3 place(kSpacingX * static_cast<float>(i % 3 - 1), 0.0f,
                     kSpacingZ * (i < 3 ? 0.5f : -0.5f));
    const float yaw = uniform_in(rng, 0.0f, 2.0f * static_cast<float>(kPi));
    Mesh m = models ? (*models)[kLayout[i]] : procedural_model(rng, i, shape_segments);
    place_model(m, place, yaw);
    const int kind = models ? kLayout[i] : i % 2;
    const std::string name = models ? kModels[kind].name : (kind == 0 ? "blob" : "torus");
    add_mesh(s, std::move(m), name + "_" + std::to_string(i), materials[kind]);
  }
  s.lights.push_back(square_light(Vec3(0.4f, 2.6f, 0.6f), 0.8f, 4.7f));
  s.camera.position = Vec3(1.5f, 1.45f, 2.4f);
  s.camera.target = Vec3(-0.05f, 0.2f, 0.0f);
  return s;
}

}  // namespace penumbra
