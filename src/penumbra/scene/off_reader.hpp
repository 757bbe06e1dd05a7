// A direct reader for the plain OFF files scanned models come as ("OFF", the counts, one
// "x y z" line per vertex, one "3 a b c" line per face), which gives the mesh assimp's import
// gives, float for float, at a fraction of its cost (bunny, 2.6 MB: ≈ 6 ms against ≈ 40 ms).
// Anything outside that subset (comments or blank-looking lines in the body, polygons, colours,
// 4D or nOFF headers, ...) is left to assimp.
#pragma once

#include <optional>
#include <string>
#include <string_view>

#include "penumbra/scene/mesh.hpp"

namespace penumbra {

/// The mesh of the OFF file `bytes` as load_mesh_file's assimp path builds it. The subset is
/// checked as strictly as validate_mesh_file checks (every index below the vertex count, exactly
/// the counted vertex and face lines, finite numbers), so a file it accepts needs no validation:
/// each vertex number read as assimp reads it (integer part to float, up to 15 fraction digits
/// scaled in double, then summed in float, times powf(10, exponent)), vertices that no face uses
/// dropped, positions equal as floats joined into the first (aiProcess_JoinIdenticalVertices), the
/// rest renumbered in order, negative zeros made positive (the node transform's + 0). std::nullopt
/// when the file is not in the subset above or holds a coordinate so small (below 1e-12 in
/// magnitude, not zero) that assimp's join tolerance could merge distinct floats.
std::optional<Mesh> read_plain_off(std::string_view bytes, const std::string& name);

/// Assimp's OFF importer reads at most 9 indices per face and drops longer polygons (a decagon
/// loads as "no faces"); its OBJ importer triangulates n-gons of any size. For an OFF file
/// already validated (validate_mesh_file) with a face of more than 9 indices: the same vertices
/// (their first three coordinate tokens, as written) and faces as an OBJ document, for assimp's
/// OBJ importer; std::nullopt when every face has at most 9 indices (assimp's OFF importer reads
/// the file as it is).
std::optional<std::string> off_polygons_as_obj(std::string_view bytes);

}  // namespace penumbra
