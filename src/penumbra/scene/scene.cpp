#include "penumbra/scene/scene.hpp"

#include <algorithm>
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

DVec3 dvec(const Vec3& v) {
  return DVec3(v);
}

double max_abs(const DVec3& v) {
  return std::max({std::fabs(v.x), std::fabs(v.y), std::fabs(v.z)});
}

/// Every coordinate a ray is built from (vertices, camera, light points) must stay well inside
/// Embree's valid ray range (|origin|, |direction| ≤ 1.8e18, `ray.valid()`) and leave float room
/// for differences and squared lengths: beyond this the answer would be rounding noise.
constexpr double kMaxCoordinate = 1e15;

bool in_range(const Vec3& v) {
  return is_finite(v) && max_abs(dvec(v)) <= kMaxCoordinate;
}

/// Removes the degenerate triangles (is_degenerate: float area² overflowed and underflowed for
/// 5e9 and 1e-12 quads before the test became relative).
size_t remove_degenerate_triangles(Mesh& mesh) {
  const size_t before = mesh.triangles.size();
  std::erase_if(mesh.triangles, [&](const Triangle& t) { return is_degenerate(mesh, t); });
  return before - mesh.triangles.size();
}

/// Lights smaller than this fraction of the scene (its bounding-box diagonal, or the light's own
/// distance from the origin, whichever is larger) are treated as point lights: their samples
/// would collapse onto the centre in float anyway, and the area formulas (r², |u × v|) underflow.
constexpr double kPointLightRelativeSize = 1e-6;

double light_size(const Light& l) {
  switch (l.shape) {
    case LightShape::rect:
      return std::max(glm::length(dvec(l.edge_u)), glm::length(dvec(l.edge_v)));
    case LightShape::disk:
    case LightShape::sphere:
      return 2.0 * l.radius;
    case LightShape::point:
      return 0.0;
  }
  return 0.0;
}

}  // namespace

DVec3 recentring_offset(const Scene& scene) {
  const Bounds3 b = scene.bounds();
  if (b.empty() || !is_finite(b.lo) || !is_finite(b.hi)) return DVec3(0.0);
  const DVec3 lo(b.lo), hi(b.hi);
  const double diagonal = glm::length(hi - lo);
  if (!(diagonal > 0.0) || !std::isfinite(diagonal)) return DVec3(0.0);
  const double step = std::exp2(std::ceil(std::log2(diagonal)));
  const DVec3 centre = 0.5 * (lo + hi);
  DVec3 offset;
  for (int a = 0; a < 3; ++a) offset[a] = step * std::round(centre[a] / step);
  return DVec3(Vec3(offset));  // a float, so that subtracting it from float coordinates is exact
}

void recentre_scene(Scene& scene) {
  const DVec3 offset = recentring_offset(scene);
  if (offset == DVec3(0.0)) return;
  const auto moved = [&](Vec3& p) { p = Vec3(DVec3(p) - offset); };
  for (Mesh& m : scene.meshes) {
    for (Vec3& p : m.positions) moved(p);
    m.source_transform[3] -= Vec4(Vec3(offset), 0.0f);
  }
  for (Light& l : scene.lights) moved(l.center);
  moved(scene.camera.position);
  moved(scene.camera.target);
  recentre_animation(scene.animation, offset);
  scene.origin += offset;
}

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
    // Per vertex and index, the message is only built on failure (≈ 300k strings for bunny).
    for (const Vec3& p : mesh.positions) {
      if (!is_finite(p)) require(false, who + ": vertex position is NaN or infinite");
      if (!in_range(p))
        require(false, who + ": vertex coordinate beyond 1e15 in magnitude (unsupported range)");
    }
    for (const Triangle& t : mesh.triangles)
      for (uint32_t v : t.v)
        if (v >= mesh.positions.size()) require(false, who + ": triangle index out of range");
    require(mesh.normals.empty() || mesh.normals.size() == mesh.positions.size(),
            who + ": normal count differs from vertex count");
    require(mesh.uvs.empty() || mesh.uvs.size() == mesh.positions.size(),
            who + ": uv count differs from vertex count");
    if (scene.materials[mesh.material].alpha_texture >= 0)
      require(!mesh.uvs.empty(), who + ": alpha-textured material needs texture coordinates");
    removed += remove_degenerate_triangles(mesh);
  }
  require(scene.triangle_count() > 0, "scene has no (non-degenerate) triangles");
  validate_animation(scene);
  // Before the light and camera checks, which then judge the coordinates methods will use.
  recentre_scene(scene);

  require(!scene.lights.empty(), "scene has no lights");
  const double scene_size = scene.bounds().diagonal();
  for (Light& l : scene.lights) {
    const std::string who = "light " + quote(l.name);
    require(is_finite(l.center) && is_finite(l.radiance),
            who + ": position or radiance not finite");
    require(in_range(l.center), who + ": centre beyond 1e15 in magnitude (unsupported range)");
    require(l.radiance.x >= 0 && l.radiance.y >= 0 && l.radiance.z >= 0,
            who + ": negative radiance");
    switch (l.shape) {
      case LightShape::rect:
        require(is_finite(l.edge_u) && is_finite(l.edge_v), who + ": edges not finite");
        require(max_abs(dvec(l.center)) + max_abs(dvec(l.edge_u)) + max_abs(dvec(l.edge_v)) <=
                    kMaxCoordinate,
                who + ": extends beyond 1e15 in magnitude (unsupported range)");
        require(sine_between(dvec(l.edge_u), dvec(l.edge_v)) > kParallelSine,
                who + ": rectangle has zero area (edges zero or parallel)");
        require(l.emission_texture < static_cast<int>(scene.textures.size()),
                who + ": emission texture index out of range");
        break;
      case LightShape::disk:
        require(is_finite(l.normal) && glm::length(dvec(l.normal)) > 0.0,
                who + ": disk normal is zero");
        [[fallthrough]];
      case LightShape::sphere:
        require(finite(l.radius) && l.radius > 0.0f, who + ": radius must be positive");
        require(max_abs(dvec(l.center)) + l.radius <= kMaxCoordinate,
                who + ": extends beyond 1e15 in magnitude (unsupported range)");
        break;
      case LightShape::point:
        break;
    }
    require(l.emission_texture < 0 || l.shape == LightShape::rect,
            who + ": only rectangle lights may have an emission texture");
    if (l.shape != LightShape::point && l.emission_texture < 0 &&
        light_size(l) <= kPointLightRelativeSize * std::max(scene_size, max_abs(dvec(l.center)))) {
      // The documented fallback for a vanishing light: a point light of the same power along
      // its axis (intensity = radiance × area, computed in double; the area may underflow float).
      double area = 0.0;
      if (l.shape == LightShape::rect)
        area = glm::length(glm::cross(dvec(l.edge_u), dvec(l.edge_v)));
      else
        area = kPi * double{l.radius} * l.radius;  // a sphere shows its silhouette disk
      l.radiance = Vec3(DVec3(l.radiance) * area);
      l.shape = LightShape::point;
      l.edge_u = l.edge_v = Vec3(0.0f);
      l.radius = 0.0f;
    }
  }

  // The camera basis in double, after normalising: finite, the view direction resolvable in
  // float at the camera's magnitude, and not parallel to `up`.
  const Camera& c = scene.camera;
  require(is_finite(c.position) && is_finite(c.target) && is_finite(c.up), "camera: not finite");
  require(in_range(c.position) && in_range(c.target),
          "camera: position or target beyond 1e15 in magnitude (unsupported range)");
  const DVec3 view = dvec(c.target) - dvec(c.position);
  require(glm::length(view) > 1e-6 * std::max(max_abs(dvec(c.position)), max_abs(dvec(c.target))),
          "camera: target equals position (or is too close to resolve in float)");
  require(sine_between(view, dvec(c.up)) > kParallelSine,
          "camera: up is zero or parallel to the view direction");
  require(finite(c.vfov_deg) && c.vfov_deg > 0.0f && c.vfov_deg < 180.0f,
          "camera: fov must be in (0, 180) degrees");
  require(c.width > 0 && c.height > 0 && c.width <= 16384 && c.height <= 16384,
          "camera: resolution must be in 1..16384");
  return removed;
}

}  // namespace penumbra
