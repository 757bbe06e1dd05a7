// `garden`: perforated occluders at scale, the Garden class of [Wang 2014 §4.3] and the textured
// occluders of [Forest 2008 ch. 5] — leaf cards whose alpha mask cuts the leaf out of the quad.
#include <algorithm>
#include <cmath>

#include "penumbra/scene/procedural.hpp"
#include "penumbra/scene/scene_classes.hpp"
#include "penumbra/scene/scene_parts.hpp"
#include "penumbra/scene/shapes.hpp"

namespace penumbra {

namespace {

struct GardenShape {
  float spacing = 0.12f;
  float jitter = 0.04f;
  float min_height = 0.3f, max_height = 0.6f, max_lean = 0.06f;
  float stem_radius = 0.005f;
  int leaves_per_plant = 256;  // 2 triangles each
  float lowest_leaf = 0.2f;    // of the stem's height
  float min_length = 0.05f, max_length = 0.09f, width_ratio = 0.5f;
  float min_elevation = -0.2f, max_elevation = 0.7f, max_twist = 0.6f;  // radians
};

/// A leaf's alpha mask in card coordinates (u across, v from the stem to the tip): a short
/// petiole, then a pointed blade with a serrated edge. 64×64 texels, 1 inside the leaf.
int add_leaf_texture(Scene& s) {
  constexpr int n = 64;
  Texture t;
  t.name = "leaf_alpha";
  t.width = t.height = n;
  t.channels = 1;
  t.texels.resize(n * n);
  const float pi = static_cast<float>(kPi);
  for (int y = 0; y < n; ++y) {
    for (int x = 0; x < n; ++x) {
      const float u = (static_cast<float>(x) + 0.5f) / n, v = (static_cast<float>(y) + 0.5f) / n;
      const float petiole_end = 0.15f;
      float half_width = 0.035f;
      if (v >= petiole_end) {
        const float s01 = (v - petiole_end) / (1.0f - petiole_end);
        half_width = 0.46f * std::pow(std::sin(pi * s01), 0.75f) *
                     (1.0f - 0.1f * std::abs(std::sin(9.0f * pi * s01)));
      }
      t.texels[y * n + x] = std::abs(u - 0.5f) < half_width ? 1.0f : 0.0f;
    }
  }
  s.textures.push_back(std::move(t));
  return static_cast<int>(s.textures.size() - 1);
}

/// One leaf card from `attach` on the stem outward: uv (0, 0)–(1, 1), v along the leaf.
Mesh make_leaf(Pcg32& rng, const GardenShape& g, const Vec3& attach) {
  const float azimuth = uniform_in(rng, 0.0f, 2.0f * static_cast<float>(kPi));
  const float elevation = uniform_in(rng, g.min_elevation, g.max_elevation);
  const Vec3 along(std::cos(elevation) * std::cos(azimuth), std::sin(elevation),
                   std::cos(elevation) * std::sin(azimuth));
  const Vec3 flat = glm::normalize(glm::cross(along, Vec3(0, 1, 0)));
  const float twist = uniform_in(rng, -g.max_twist, g.max_twist);
  const Vec3 across = std::cos(twist) * flat + std::sin(twist) * glm::cross(along, flat);
  const float length = uniform_in(rng, g.min_length, g.max_length);
  const float width = g.width_ratio * length;
  Mesh leaf = make_quad(attach + 0.5f * length * along, width * across, length * along);
  float lowest = kInfinity;
  for (const Vec3& p : leaf.positions) lowest = std::min(lowest, p.y);
  const float clearance = 0.002f;
  if (lowest < clearance)
    for (Vec3& p : leaf.positions) p.y += clearance - lowest;
  return leaf;
}

}  // namespace

Scene make_garden_scene(uint64_t seed, int plants_per_side) {
  const int rows = std::max(plants_per_side, 0);  // rows × rows plants on a jittered grid
  const GardenShape g;
  Pcg32 rng(seed, /*stream=*/2);
  Mesh stems, leaves;
  const size_t plants = static_cast<size_t>(rows) * rows;
  leaves.positions.reserve(plants * g.leaves_per_plant * 4);
  leaves.uvs.reserve(plants * g.leaves_per_plant * 4);
  leaves.triangles.reserve(plants * g.leaves_per_plant * 2);
  const float origin = -0.5f * g.spacing * static_cast<float>(rows - 1);
  for (int i = 0; i < rows; ++i) {
    for (int j = 0; j < rows; ++j) {
      // One draw per statement: the order of a function's arguments is unspecified.
      const float jitter_x = uniform_in(rng, -g.jitter, g.jitter);
      const float jitter_z = uniform_in(rng, -g.jitter, g.jitter);
      // The stem starts one radius up: its corners, off a leaning axis, stay above the ground.
      const Vec3 base(origin + g.spacing * static_cast<float>(i) + jitter_x, g.stem_radius,
                      origin + g.spacing * static_cast<float>(j) + jitter_z);
      const float lean_x = uniform_in(rng, -g.max_lean, g.max_lean);
      const float height = uniform_in(rng, g.min_height, g.max_height);
      const float lean_z = uniform_in(rng, -g.max_lean, g.max_lean);
      const Vec3 top = base + Vec3(lean_x, height, lean_z);
      const float phase = uniform_in(rng, 0.0f, 2.0f * static_cast<float>(kPi));
      append_mesh(stems, make_open_prism(base, top, g.stem_radius, phase));
      for (int k = 0; k < g.leaves_per_plant; ++k) {
        const float t = uniform_in(rng, g.lowest_leaf, 1.0f);
        append_mesh(leaves, make_leaf(rng, g, base + t * (top - base)));
      }
    }
  }

  Scene s;
  s.name = "garden";
  add_ground(s);
  const int leaf_texture = add_leaf_texture(s);
  add_mesh(s, std::move(stems), "stems", add_material(s, "stems", Vec3(0.35f, 0.45f, 0.2f)));
  add_mesh(s, std::move(leaves), "leaves",
           add_material(s, "leaves", Vec3(0.25f, 0.6f, 0.2f), leaf_texture));
  // A large light high above: the leaves' holes and edges blur into a dappled penumbra.
  s.lights.push_back(square_light(Vec3(0.5f, 3.0f, 0.3f), 1.0f, 4.5f));
  s.camera.position = Vec3(2.3f, 2.0f, 2.9f);
  s.camera.target = Vec3(0.0f, 0.2f, 0.0f);
  return s;
}

}  // namespace penumbra
