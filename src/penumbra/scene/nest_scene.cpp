// `nest`: fragmented geometry, the Bird Nest class of [Wang 2014 §4.3] — thousands of thin
// disconnected twigs, where nearly every edge is a silhouette and shadows are mostly penumbra.
#include <algorithm>
#include <cmath>

#include "penumbra/scene/procedural.hpp"
#include "penumbra/scene/scene_classes.hpp"
#include "penumbra/scene/scene_parts.hpp"
#include "penumbra/scene/shapes.hpp"

namespace penumbra {

namespace {

struct NestShape {
  Vec3 center{0, 0.68f, 0};  // of the sphere the bowl is cut from
  float inner_radius = 0.42f, outer_radius = 0.58f;
  float rim = 0.25f;  // highest twig centre, as y of its direction from the centre (0: equator)
  float min_length = 0.06f, max_length = 0.16f;
  float min_radius = 0.0012f, max_radius = 0.0025f;  // of the twig's triangular cross-section
  float wander = 0.45f;  // how far a twig's axis strays from the shell's tangent plane
};

/// One twig: its centre in the shell, its axis mostly along the shell (nests are woven), lifted
/// where it would poke through the ground.
Mesh make_twig(Pcg32& rng, const NestShape& n) {
  Vec3 dir = random_direction(rng);
  while (dir.y > n.rim) dir = random_direction(rng);
  const float r = uniform_in(rng, n.inner_radius, n.outer_radius);
  const Vec3 centre = n.center + r * dir;
  const Vec3 along = random_direction(rng);
  Vec3 axis = along - glm::dot(along, dir) * dir + n.wander * random_direction(rng);
  if (!(glm::length(axis) > 1e-3f)) axis = Vec3(1, 0, 0);
  axis = glm::normalize(axis);
  const float half = 0.5f * uniform_in(rng, n.min_length, n.max_length);
  const float radius = uniform_in(rng, n.min_radius, n.max_radius);
  const float phase = uniform_in(rng, 0.0f, 2.0f * static_cast<float>(kPi));
  Vec3 a = centre - half * axis, b = centre + half * axis;
  const float clearance = 0.002f;
  const float lift = std::max(0.0f, clearance + radius - std::min(a.y, b.y));
  a.y += lift;
  b.y += lift;
  return make_open_prism(a, b, radius, phase);
}

}  // namespace

Scene make_nest_scene(uint64_t seed, int twig_count) {
  const NestShape shape;
  Pcg32 rng(seed, /*stream=*/1);
  Mesh twigs;
  twigs.positions.reserve(6 * static_cast<size_t>(std::max(twig_count, 0)));
  twigs.triangles.reserve(6 * static_cast<size_t>(std::max(twig_count, 0)));
  for (int i = 0; i < twig_count; ++i) append_mesh(twigs, make_twig(rng, shape));

  Scene s;
  s.name = "nest";
  add_ground(s);
  add_mesh(s, std::move(twigs), "twigs", add_material(s, "twigs", Vec3(0.55f, 0.42f, 0.28f)));
  // Above and to the side, so the bowl's shadow falls on open ground; the light is large enough
  // that the gaps between twigs blur into penumbra.
  s.lights.push_back(square_light(Vec3(0.9f, 2.8f, 0.5f), 0.8f, 5.5f));
  s.camera.position = Vec3(-0.8f, 1.9f, 2.4f);
  s.camera.target = Vec3(-0.3f, 0.3f, -0.1f);
  return s;
}

}  // namespace penumbra
