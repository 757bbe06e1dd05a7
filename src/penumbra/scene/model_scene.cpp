#include "penumbra/scene/model_scene.hpp"

#include <algorithm>
#include <array>
#include <cctype>

#include "penumbra/core/error.hpp"
#include "penumbra/scene/mesh_loader.hpp"

namespace penumbra {

namespace {

std::string lower_extension(const std::filesystem::path& file) {
  std::string ext = file.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return ext;
}

}  // namespace

ModelUp parse_model_up(std::string_view text) {
  if (text == "y") return ModelUp::y;
  if (text == "z") return ModelUp::z;
  if (text == "auto") return ModelUp::automatic;
  throw Error("--up: expected y, z or auto, got '" + std::string(text) + "'");
}

ModelUp resolve_model_up(ModelUp up, const std::filesystem::path& file) {
  if (up != ModelUp::automatic) return up;
  static const std::array<const char*, 7> z_up = {".stl",   ".3mf", ".amf",   ".3ds",
                                                  ".blend", ".ifc", ".ifczip"};
  const std::string ext = lower_extension(file);
  return std::find(z_up.begin(), z_up.end(), ext) != z_up.end() ? ModelUp::z : ModelUp::y;
}

bool is_model_path(const std::filesystem::path& path) {
  return lower_extension(path) != ".json";
}

Scene load_model_scene(const std::filesystem::path& file, const ModelFraming& framing) {
  ModelFraming f = framing;
  f.up = resolve_model_up(framing.up, file);
  Scene s = frame_model(load_mesh_file(file), file.stem().string(), f, file);
  validate_scene(s);
  return s;
}

}  // namespace penumbra
