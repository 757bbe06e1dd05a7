// Scenes by name that need no files (quad, spheres, fence, default; the scene classes nest,
// garden, herd of scene_classes.hpp) and the fixed model scenes (bunny, dragon, armadillo,
// elephant) built around fetched models.
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "penumbra/scene/scene.hpp"

namespace penumbra {

struct BuiltinSceneInfo {
  std::string name;
  std::string description;
  bool needs_models = false;  // the model scenes: run scripts/fetch-models.sh first
};

const std::vector<BuiltinSceneInfo>& builtin_scenes();
bool is_builtin_scene(std::string_view name);

/// Where the named built-in scene's content comes from, on one line: "procedural", its seed, the
/// model file found, or what is missing and how to fetch it (herd: which of its two forms loads).
/// Empty for a name that is not built in.
std::string builtin_scene_origin(std::string_view name);

/// Builds the named scene; throws Error for an unknown name or a missing model file (the message
/// says how to fetch it).
Scene make_builtin_scene(std::string_view name);

/// Geometry of the `quad` scene, exposed so tests can evaluate its closed-form penumbra.
struct QuadSceneGeometry {
  float light_height = 3.0f;  // square light centred on the y axis, facing down
  float light_side = 1.0f;
  float occluder_height = 1.0f;  // square occluder parallel to the light and the ground
  float occluder_side = 1.0f;
};
inline constexpr QuadSceneGeometry kQuadScene{};

/// Closed-form visible fraction of the `quad` scene's light at point (x, y, z) below the occluder
/// (y < occluder height): the occluder projects from the point onto the light plane as an
/// axis-aligned square, so the covered fraction is the product of two interval overlaps.
double quad_scene_visible_fraction(double x, double y, double z);
inline double quad_scene_visible_fraction(double x, double z) {
  return quad_scene_visible_fraction(x, 0.0, z);
}

}  // namespace penumbra
