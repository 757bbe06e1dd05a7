// A complete frame description: meshes, materials, textures, lights and the camera.
#pragma once

#include <string>
#include <vector>

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

  Bounds3 bounds() const;  // of all meshes
  size_t triangle_count() const;
  const Material& material_of(const Mesh& mesh) const { return materials[mesh.material]; }
};

/// Checks a scene built in code or loaded from a file: indices in range, finite numbers, at least
/// one light, positive light sizes, a usable camera. Throws Error naming the first problem.
/// Removes degenerate (zero-area or non-finite) triangles — the documented robust fallback — and
/// returns how many it removed.
size_t validate_scene(Scene& scene);

}  // namespace penumbra
