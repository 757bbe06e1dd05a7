// A scene around any mesh file: the layout of the built-in `bunny` (model scaled to a bounding-box
// diagonal of 1 and standing on the ground at y = 0, a square light above it, the camera looking
// at it), so `penumbra render --scene my_model.obj` works without writing a scene file.
#pragma once

#include <filesystem>
#include <string>
#include <string_view>

#include "penumbra/scene/scene.hpp"

namespace penumbra {

/// Which model axis points up. `automatic`: z for the formats whose convention is Z-up (STL, 3MF,
/// AMF, 3DS, Blender, IFC: CAD and 3D-printing formats) and y for every other one (OBJ, PLY,
/// OFF, glTF — Y-up by its specification —, FBX and COLLADA, whose up axis assimp applies).
enum class ModelUp { y, z, automatic };

/// Parses "y", "z" or "auto"; throws Error otherwise.
ModelUp parse_model_up(std::string_view text);
/// The axis `up` means for `file` (resolves `automatic` by the file's extension).
ModelUp resolve_model_up(ModelUp up, const std::filesystem::path& file);

struct ModelFraming {
  float light_size = 0.5f;    // side of the square light, in model diagonals
  float light_height = 2.0f;  // light centre above the model's centre, in model diagonals
  ModelUp up = ModelUp::automatic;
};

/// The model-to-world matrix of the layout: `up` turned to +y, scaled to a diagonal of 1,
/// centred on the y axis, lowest point at y = 0.
Mat4 model_framing_matrix(const Mesh& model, ModelUp up);

/// Builds the framed scene from a loaded mesh (positions in the model's own coordinates).
/// `source`, when given, is recorded in the mesh so that a scene file written from the scene
/// refers to the model file instead of copying its triangles.
Scene frame_model(Mesh model, const std::string& name, const ModelFraming& framing,
                  const std::filesystem::path& source = {});

/// Loads any mesh file assimp reads and frames it; the scene is named after the file.
Scene load_model_scene(const std::filesystem::path& file, const ModelFraming& framing = {});

/// Does this path look like a mesh file rather than a JSON scene (any extension but .json)?
bool is_model_path(const std::filesystem::path& path);

}  // namespace penumbra
