// Mesh files through assimp (OBJ, PLY, OFF, glTF, STL, ...).
#pragma once

#include <filesystem>
#include <optional>

#include "penumbra/scene/mesh.hpp"
#include "penumbra/scene/mesh_header.hpp"

namespace penumbra {

/// Loads every mesh of the file merged into one triangle mesh (node transforms applied;
/// polygons triangulated; vertices joined by position). Keeps normals and the first UV channel
/// when present. Throws Error with assimp's reason for a missing, unreadable or empty file.
/// A plain OFF file (off_reader.hpp) is read directly; OFF, PLY and OBJ files are otherwise
/// validated (mesh_header.hpp), then every file goes through import_mesh_file.
Mesh load_mesh_file(const std::filesystem::path& path);

/// The whole file, after checking it is a regular file (a FIFO or /dev/zero would be read
/// forever). Throws Error ("cannot load mesh ...").
std::string read_mesh_file_bytes(const std::filesystem::path& path);

/// load_mesh_file's assimp import, for a file validated to `counts` (std::nullopt: not counted):
/// throws Error unless assimp reads that many triangles. Exposed so that tests can compare the
/// direct OFF reader with it.
Mesh import_mesh_file(const std::filesystem::path& path,
                      const std::optional<MeshFileCounts>& counts);

}  // namespace penumbra
