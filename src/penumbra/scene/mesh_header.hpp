// Validation of OFF, PLY, OBJ and STL files before assimp reads them. Assimp trusts their headers:
// a PLY without `end_header` spins or crashes, a face with no indices trips an assertion, a huge
// count allocates gigabytes, and bad indices or short bodies are clamped or fabricated silently.
// These checks walk the whole file (header, every vertex and face record) and reject what assimp
// would mishandle, with a one-line reason.
#pragma once

#include <cstddef>
#include <optional>
#include <string_view>

namespace penumbra {

/// What a validated OFF or PLY file holds, to cross-check assimp's result against.
struct MeshFileCounts {
  size_t vertices = 0;
  size_t faces = 0;
  size_t triangles = 0;  // Σ (n − 2) over faces of n ≥ 3 indices: what triangulation must yield
};

/// `bytes` is the file's content, `extension` its lower-case extension (".off", ".ply", ".obj",
/// ".stl"). Returns the counts for OFF, PLY and STL files, std::nullopt for other formats; throws
/// Error naming the defect for a malformed OFF, PLY, OBJ or STL file (OBJ: every statement and
/// vertex reference; STL: the binary size or every ASCII statement).
std::optional<MeshFileCounts> validate_mesh_file(std::string_view bytes,
                                                 std::string_view extension);

}  // namespace penumbra
