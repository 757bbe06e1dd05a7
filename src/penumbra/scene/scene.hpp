// A complete frame description: meshes, materials, textures, lights and the camera.
#pragma once

#include <string>
#include <vector>

#include "penumbra/scene/animation.hpp"
#include "penumbra/scene/camera.hpp"
#include "penumbra/scene/light.hpp"
#include "penumbra/scene/material.hpp"
#include "penumbra/scene/mesh.hpp"
#include "penumbra/scene/texture.hpp"

namespace penumbra {

struct Scene {
  std::string name;
  std::vector<Mesh> meshes;
  std::vector<Material> materials;
  std::vector<Texture> textures;
  std::vector<Light> lights;
  Camera camera;
  Vec3 ambient{0.02f};  // constant ambient radiance added to every surface, linear RGB
  /// Where the scene's coordinates are measured from: world = stored + origin (double). Scenes far
  /// from the world origin are moved next to it (recentre_scene), so that float resolution and
  /// the self-intersection offset are those of a scene at the origin.
  DVec3 origin{0.0};
  /// Keyframed motion over time (empty: a still scene); the members above are its rest pose.
  Animation animation;

  Bounds3 bounds() const;  // of all meshes
  size_t triangle_count() const;
  const Material& material_of(const Mesh& mesh) const { return materials[mesh.material]; }
};

/// Checks a scene built in code or loaded from a file: indices in range, finite numbers, at least
/// one light, positive light sizes, a usable camera. Throws Error naming the first problem.
/// Removes degenerate (zero-area or non-finite) triangles — the documented robust fallback — and
/// returns how many it removed.
size_t validate_scene(Scene& scene);

/// The translation that brings the scene's meshes next to the world origin: their bounding-box
/// centre rounded to a multiple of the power of two at or above their diagonal. Zero for a scene
/// whose centre lies within half that step of the origin (every scene built around it), so
/// such scenes keep their coordinates bit for bit. Exact in float: every coordinate minus it
/// is representable where the meshes lie.
DVec3 recentring_offset(const Scene& scene);

/// Moves every mesh, light and the camera by −recentring_offset (exact in float) and adds it to
/// `scene.origin`: a scene then renders the same wherever it is placed. validate_scene calls it.
void recentre_scene(Scene& scene);

}  // namespace penumbra
