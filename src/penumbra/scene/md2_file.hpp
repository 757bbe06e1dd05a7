// MD2 (Quake II) models: validated in full before assimp reads them (its importers trust their
// files), and read as every keyframe at once, with one vertex order for all frames.
#pragma once

#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "penumbra/scene/mesh.hpp"

namespace penumbra {

struct Md2Model {
  /// Keyframe 0, as load_mesh_file returns it.
  Mesh rest;
  /// Every keyframe's positions (the file's coordinates), in rest's vertex order.
  std::vector<std::vector<Vec3>> frames;
  std::vector<std::string> frame_names;
};

/// Checks the header, every offset and size against the file, and every triangle's vertex and
/// texture-coordinate index; returns the frame names. Throws Error naming the first problem.
std::vector<std::string> validate_md2(std::string_view bytes);

/// Imports each keyframe of the validated file (assimp reads one per import, chosen by
/// AI_CONFIG_IMPORT_MD2_KEYFRAME) without assimp's vertex joining, then joins the corners that
/// agree in texture coordinates and in position in every frame: the same vertices whatever
/// frame is shown. Throws Error (prefixed "cannot load mesh") when it cannot.
Md2Model read_md2(const std::filesystem::path& path, std::string_view bytes);

}  // namespace penumbra
