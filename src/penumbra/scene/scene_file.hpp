// JSON scene files (format: docs/scene-format.md) and scene lookup by name or path.
#pragma once

#include <filesystem>
#include <string_view>

#include "penumbra/scene/model_scene.hpp"
#include "penumbra/scene/scene.hpp"

namespace penumbra {

/// Parses a JSON scene file, loads its meshes and textures (relative paths are resolved against
/// the folder of the JSON file) and validates the result (validate_scene). Throws Error with a
/// one-line message "<file>: <json path>: <problem>" for any problem: syntax errors (with line
/// and column), unknown keys, wrong types, missing fields, non-finite or out-of-range numbers,
/// unknown material names, missing or unreadable mesh/texture files.
Scene load_scene_file(const std::filesystem::path& path);

/// A built-in scene name (see builtin_scenes()), the path of a JSON scene file (.json), or the
/// path of any mesh file assimp reads, framed by `framing` (model_scene.hpp). Throws Error
/// listing the built-in names when `name_or_path` is none of them.
Scene load_scene(std::string_view name_or_path, const ModelFraming& framing = {});

/// What load_scene checks before it reads anything: `name_or_path` is a built-in scene name or an
/// existing regular file; throws load_scene's Error otherwise. For commands that take several
/// scenes, so that a bad last one is reported before the first is rendered.
void check_scene_name(std::string_view name_or_path);

}  // namespace penumbra
