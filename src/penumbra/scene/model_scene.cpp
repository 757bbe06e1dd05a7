#include "penumbra/scene/model_scene.hpp"

#include <algorithm>
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

ModelUp resolve_model_up(ModelUp up, const Mesh& model) {
  if (up != ModelUp::automatic) return up;
  const Bounds3 b = model.bounds();
  const float slab = 0.02f * b.diagonal();
  // Area of the triangles lying in the lowest slab along axis `a` (1 = y, 2 = z).
  const auto support = [&](int a) {
    double area = 0.0;
    for (size_t t = 0; t < model.triangles.size(); ++t) {
      const Vec3 p0 = model.vertex(t, 0), p1 = model.vertex(t, 1), p2 = model.vertex(t, 2);
      if (std::max({p0[a], p1[a], p2[a]}) <= b.lo[a] + slab)
        area += 0.5 * glm::length(glm::cross(p1 - p0, p2 - p0));
    }
    return area;
  };
  return support(2) > 2.0 * support(1) ? ModelUp::z : ModelUp::y;
}

bool is_model_path(const std::filesystem::path& path) {
  return lower_extension(path) != ".json";
}

Scene load_model_scene(const std::filesystem::path& file, const ModelFraming& framing) {
  ModelFraming f = framing;
  Mesh model = load_mesh_file(file);
  f.up = resolve_model_up(framing.up, model);
  Scene s = frame_model(std::move(model), file.stem().string(), f, file);
  validate_scene(s);
  return s;
}

}  // namespace penumbra
