// The scene file's "animation" object (docs/scene-format.md, Animation): read into a Scene's
// Animation, and written back. Internal to the scene loader and writer.
#pragma once

#include <filesystem>
#include <functional>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "penumbra/scene/scene.hpp"

namespace penumbra {

namespace scene_json {
class TextureCache;
}

/// Reads `j` (the value of the top-level "animation" key) against the scene's meshes and lights,
/// named as in the file. Positions are moved by −origin like the rest of the file's. Throws Error
/// naming the JSON path of the first problem.
Animation parse_animation(const nlohmann::json& j, const Scene& scene,
                          scene_json::TextureCache& textures, const std::filesystem::path& base,
                          const DVec3& origin);

/// How the writer names meshes and lights and stores what is not JSON: an emission texture (returns
/// its relative path), a generated vertex clip's key `key` of mesh `mesh` (writes the mesh with
/// those positions as a file, returns its relative path).
struct AnimationAssets {
  /// The names the meshes and lights are written under (unique), by index.
  std::vector<std::string> mesh_names, light_names;
  /// Which meshes are written as a reference to their source file (a clip of that file can be
  /// named); the others are written as PLY files with the identity transform.
  std::vector<bool> mesh_written_as_file;
  std::function<std::string(int texture)> emission_texture;
  std::function<std::string(int mesh, size_t key, const std::vector<Vec3>& positions)> clip_key;
};

/// The scene's animation as the scene file's "animation" object (null for a still scene without a
/// time range).
nlohmann::json animation_json(const Scene& scene, const AnimationAssets& assets);

}  // namespace penumbra
