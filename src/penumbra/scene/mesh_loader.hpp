// Mesh files through assimp (OBJ, PLY, OFF, glTF, STL, ...).
#pragma once

#include <filesystem>

#include "penumbra/scene/mesh.hpp"

namespace penumbra {

/// Loads every mesh of the file merged into one triangle mesh (node transforms applied;
/// polygons triangulated; vertices joined by position). Keeps normals and the first UV channel
/// when present. Throws Error with assimp's reason for a missing, unreadable or empty file.
Mesh load_mesh_file(const std::filesystem::path& path);

}  // namespace penumbra
