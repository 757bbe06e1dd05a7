// A scene around any mesh file: the layout of the built-in `bunny` (model scaled to a bounding-box
// diagonal of 1 and standing on the ground at y = 0, a square light above it, the camera looking
// at it), so `penumbra render --scene my_model.obj` works without writing a scene file.
#pragma once

#include <filesystem>
#include <string>
#include <string_view>

#include "penumbra/scene/scene.hpp"

namespace penumbra {

/// Which model axis points up. `automatic` looks at the geometry, since file formats do not say
/// reliably (STL files come both ways): a model stands on its base, so the axis whose lowest 2%
/// slab holds the larger area of triangles (the feet, the base plate, the cut bottom of a scan)
/// is up; z wins only with more than twice y's area, as most formats (OBJ, glTF, PLY, ...) are
/// Y-up.
enum class ModelUp { y, z, automatic };

/// Parses "y", "z" or "auto"; throws Error otherwise.
ModelUp parse_model_up(std::string_view text);
/// The axis `up` means for `model` (resolves `automatic` from the geometry).
ModelUp resolve_model_up(ModelUp up, const Mesh& model);

struct ModelFraming {
  float light_size = 0.5f;    // side of the square light, in model diagonals
  float light_height = 2.0f;  // light centre above the model's centre, in model diagonals
  ModelUp up = ModelUp::automatic;
  /// Move the camera along the `bunny` view direction until the model's bounding sphere just
  /// fills the vertical field of view. The built-in model scenes keep the fixed benchmark camera
  /// at (1.5, 1.2, 1.5) (where the bunny covers 6% of the image, a thin model 3%).
  bool fit_camera = true;
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
