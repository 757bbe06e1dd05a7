// glTF animations as vertex clips: at each key time of an animation, its morph-target weights,
// node transforms and skins (linear blend skinning) applied, giving the vertex positions of the
// merged mesh load_mesh_file reads.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "penumbra/core/math.hpp"

namespace penumbra {

struct MorphClip {
  std::string name;                          // the glTF animation's name ("animation<i>" if none)
  std::vector<double> times_s;               // every weight key time of its morph channels
  std::vector<std::vector<Vec3>> positions;  // the merged mesh's positions at each time
};

/// The file's animations, in file order: positions are the morphed vertices, skinned by their
/// joints' animated transforms (glTF ignores a skinned mesh's own node) or placed by their node's
/// animated transform. The positions follow load_mesh_file's vertex order (the same
/// import); throws Error when the file cannot be read or its vertex count differs from
/// `rest_vertices`.
std::vector<MorphClip> read_gltf_morph_clips(const std::filesystem::path& path,
                                             size_t rest_vertices);

}  // namespace penumbra
