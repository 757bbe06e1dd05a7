#include "penumbra/scene/scene.hpp"

#include <cmath>
#include <string>

#include "penumbra/core/error.hpp"

namespace penumbra {

Bounds3 Scene::bounds() const {
  Bounds3 b;
  for (const Mesh& m : meshes) b.extend(m.bounds());
  return b;
}

size_t Scene::triangle_count() const {
  size_t n = 0;
  for (const Mesh& m : meshes) n += m.triangle_count();
  return n;
}

namespace {

void require(bool ok, const std::string& what) {
  if (!ok) throw Error(what);
}

bool finite(float x) {
  return std::isfinite(x);
}

size_t remove_degenerate_triangles(Mesh& mesh) {
  const size_t before = mesh.triangles.size();
  std::erase_if(mesh.triangles, [&](const Triangle& t) {
    const Vec3 a = mesh.positions[t.v[0]], b = mesh.positions[t.v[1]], c = mesh.positions[t.v[2]];
    const Vec3 n = glm::cross(b - a, c - a);
    const float area2 = glm::dot(n, n);
    return !(area2 > 0.0f) || !std::isfinite(area2);
  });
  return before - mesh.triangles.size();
}

}  // namespace

size_t validate_scene(Scene& scene) {
  require(!scene.materials.empty(), "scene has no materials");
  for (const Material& m : scene.materials) {
    require(is_finite(m.albedo), "material " + quote(m.name) + ": albedo is not finite");
    require(m.alpha_texture < static_cast<int>(scene.textures.size()),
            "material " + quote(m.name) + ": alpha texture index out of range");
    require(finite(m.transmittance) && m.transmittance >= 0.0f && m.transmittance < 1.0f,
            "material " + quote(m.name) + ": transmittance must be in [0, 1)");
  }
  for (const Texture& t : scene.textures) {
    require(t.width > 0 && t.height > 0 && t.channels > 0 &&
                t.texels.size() == static_cast<size_t>(t.width) * t.height * t.channels,
            "texture " + quote(t.name) + ": size does not match its texels");
  }
  size_t removed = 0;
  for (Mesh& mesh : scene.meshes) {
    const std::string who = "mesh " + quote(mesh.name);
    require(mesh.material >= 0 && mesh.material < static_cast<int>(scene.materials.size()),
            who + ": material index out of range");
    for (const Vec3& p : mesh.positions)
      require(is_finite(p), who + ": vertex position is NaN or infinite");
    for (const Triangle& t : mesh.triangles)
      for (uint32_t v : t.v)
        require(v < mesh.positions.size(), who + ": triangle index out of range");
    require(mesh.normals.empty() || mesh.normals.size() == mesh.positions.size(),
            who + ": normal count differs from vertex count");
    require(mesh.uvs.empty() || mesh.uvs.size() == mesh.positions.size(),
            who + ": uv count differs from vertex count");
    if (scene.materials[mesh.material].alpha_texture >= 0)
      require(!mesh.uvs.empty(), who + ": alpha-textured material needs texture coordinates");
    removed += remove_degenerate_triangles(mesh);
  }
  require(scene.triangle_count() > 0, "scene has no (non-degenerate) triangles");

  require(!scene.lights.empty(), "scene has no lights");
  for (const Light& l : scene.lights) {
    const std::string who = "light " + quote(l.name);
    require(is_finite(l.center) && is_finite(l.radiance),
            who + ": position or radiance not finite");
    require(l.radiance.x >= 0 && l.radiance.y >= 0 && l.radiance.z >= 0,
            who + ": negative radiance");
    switch (l.shape) {
      case LightShape::rect:
        require(is_finite(l.edge_u) && is_finite(l.edge_v), who + ": edges not finite");
        require(glm::length(glm::cross(l.edge_u, l.edge_v)) > 1e-12f,
                who + ": rectangle has zero area");
        require(l.emission_texture < static_cast<int>(scene.textures.size()),
                who + ": emission texture index out of range");
        break;
      case LightShape::disk:
        require(is_finite(l.normal) && glm::length(l.normal) > 1e-12f,
                who + ": disk normal is zero");
        require(finite(l.radius) && l.radius > 0.0f, who + ": radius must be positive");
        break;
      case LightShape::sphere:
        require(finite(l.radius) && l.radius > 0.0f, who + ": radius must be positive");
        break;
      case LightShape::point:
        break;
    }
    require(l.emission_texture < 0 || l.shape == LightShape::rect,
            who + ": only rectangle lights may have an emission texture");
  }

  const Camera& c = scene.camera;
  require(is_finite(c.position) && is_finite(c.target) && is_finite(c.up), "camera: not finite");
  require(glm::length(c.target - c.position) > 0.0f, "camera: target equals position");
  require(glm::length(glm::cross(c.target - c.position, c.up)) > 0.0f,
          "camera: up is parallel to the view direction");
  require(finite(c.vfov_deg) && c.vfov_deg > 0.0f && c.vfov_deg < 180.0f,
          "camera: fov must be in (0, 180) degrees");
  require(c.width > 0 && c.height > 0 && c.width <= 16384 && c.height <= 16384,
          "camera: resolution must be in 1..16384");
  return removed;
}

}  // namespace penumbra
