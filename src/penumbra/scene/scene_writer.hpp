// Writes any scene (built-in, loaded or a framed model) as a JSON scene file (docs/scene-format.md)
// that loads back into the same scene: the same floats, so the same render.
#pragma once

#include <filesystem>

#include "penumbra/scene/scene.hpp"

namespace penumbra {

/// Writes `json_path`. A mesh that came from a file, unchanged since (checked by reloading it),
/// is written as a reference to that file with its transform matrix; every other mesh is written
/// as a binary PLY (positions, normals, texture coordinates: exact floats) in the folder
/// `<json stem>_meshes/` beside the file, and textures as PNG there. Throws Error when it cannot.
void write_scene_file(const Scene& scene, const std::filesystem::path& json_path);

}  // namespace penumbra
