// Validation of glTF 2.0 files (.gltf JSON, .glb container) before assimp reads them. Assimp
// recurses once per node level (a 20 000-deep chain overflows the stack), and accepts malformed
// accessors (VEC2 positions, index counts not a multiple of 3) and out-of-range indices, which it
// drops silently. These checks read the JSON structure only (never the buffers); what needs the
// buffers is cross-checked on assimp's result through the triangle count.
#pragma once

#include <optional>
#include <string_view>

#include "penumbra/scene/mesh_header.hpp"

namespace penumbra {

/// Deepest node hierarchy accepted (root = depth 0).
inline constexpr int kMaxGltfNodeDepth = 1024;

/// `bytes` is a .gltf (JSON) or .glb file's content. Throws Error naming the defect: a GLB header
/// or chunk that does not match the file, invalid JSON, node indices out of range, a node with two
/// parents or in a cycle, a hierarchy deeper than kMaxGltfNodeDepth, a triangle primitive whose
/// POSITION is not a float VEC3 accessor or whose index count is not a multiple of 3 or whose
/// `max` index reaches the vertex count. Returns the triangles the default scene must yield when
/// every primitive is a plain triangle list (std::nullopt otherwise: strips, fans, compression).
std::optional<MeshFileCounts> validate_gltf(std::string_view bytes, bool glb);

}  // namespace penumbra
