// Running methods on small frames of built-in scenes, for tests.
#pragma once

#include <cmath>
#include <map>
#include <memory>
#include <string>

#include "penumbra/metrics/error_metrics.hpp"
#include "penumbra/pipeline/frame.hpp"
#include "penumbra/pipeline/outputs.hpp"
#include "penumbra/scene/builtin_scenes.hpp"
#include "penumbra/scene/shapes.hpp"

namespace penumbra::test {

/// A scene and a frame over it (the frame points into the scene, so they live together).
struct TestFrame {
  std::unique_ptr<Scene> scene;
  std::unique_ptr<Frame> frame;

  MethodResult run(const std::string& method,
                   const std::map<std::string, std::string>& options = {},
                   bool want_masks = false) const {
    const MethodInfo& info = MethodRegistry::builtin().get(method);
    return frame->run(info, resolve_options(info, options), want_masks);
  }
};

/// The spheres scene under a round light (disk or sphere, radius 0.4, facing down).
inline Scene round_light_scene(LightShape shape) {
  Scene scene = make_builtin_scene("spheres");
  Light& l = scene.lights[0];
  l.shape = shape;
  l.radius = 0.4f;
  l.normal = Vec3(0, -1, 0);
  return scene;
}

/// Does the segment o → o + d (parameter in (0, 1]) cross triangle abc? Möller–Trumbore in double
/// precision: the brute-force oracle tests use, independent of every BVH. Optionally returns the
/// hit's barycentrics (Embree's convention: p = (1−u−v) a + u b + v c).
inline bool segment_crosses_triangle(const DVec3& o, const DVec3& d, const DVec3& a, const DVec3& b,
                                     const DVec3& c, double* hit_u = nullptr,
                                     double* hit_v = nullptr) {
  const DVec3 e1 = b - a, e2 = c - a, pv = glm::cross(d, e2);
  const double det = glm::dot(e1, pv);
  if (std::abs(det) < 1e-300) return false;
  const DVec3 tv = o - a;
  const double u = glm::dot(tv, pv) / det;
  const DVec3 qv = glm::cross(tv, e1);
  const double v = glm::dot(d, qv) / det, t = glm::dot(e2, qv) / det;
  if (hit_u) *hit_u = u;
  if (hit_v) *hit_v = v;
  return u >= 0 && v >= 0 && u + v <= 1 && t > 0 && t <= 1;
}

/// A sphere with holes (open) and a third of its faces flipped (inconsistent orientation), flat
/// shaded: the degenerate-topology mesh several tests share.
inline Mesh open_flipped_sphere() {
  Mesh sphere = make_sphere(Vec3(0.2f, 0.8f, 0.1f), 0.45f, 10, 20);
  std::vector<Triangle> kept;
  for (size_t t = 0; t < sphere.triangles.size(); ++t) {
    if (t % 19 >= 15) continue;  // holes
    Triangle tri = sphere.triangles[t];
    if (t % 3 == 0) std::swap(tri.v[1], tri.v[2]);
    kept.push_back(tri);
  }
  sphere.triangles = kept;
  sphere.normals.clear();
  return sphere;
}

/// `quad` with its occluder replaced by the open, flipped sphere plus a fin of three triangles on
/// one edge (non-manifold), lit from the side so the open part matters.
inline Scene open_non_manifold_scene() {
  Scene s = make_builtin_scene("quad");
  Mesh sphere = open_flipped_sphere();  // the fin vertices below get no normals
  const uint32_t a = sphere.triangles[5].v[0], b = sphere.triangles[5].v[1];
  for (int k = 0; k < 3; ++k) {
    sphere.positions.push_back(
        0.5f * (sphere.positions[a] + sphere.positions[b]) +
        Vec3(0.3f * static_cast<float>(k), 0.4f, -0.2f * static_cast<float>(k)));
    sphere.triangles.push_back({{a, b, static_cast<uint32_t>(sphere.positions.size() - 1)}});
  }
  sphere.name = "open";
  sphere.material = 1;
  s.meshes[1] = sphere;
  s.lights[0].center = Vec3(1.2f, 2.5f, 0.4f);
  return s;
}

/// `s` with every alpha texture removed: perforated occluders become opaque for every method.
inline Scene without_alpha(Scene s) {
  for (Material& m : s.materials) m.alpha_texture = -1;
  return s;
}

/// `scene` under a 2×2 RGB emission texture (every texel a different colour, so each channel's
/// emission is non-uniform and the three channels differ).
inline Scene with_textured_light(Scene s) {
  Texture tex;
  tex.name = "emission_2x2";
  tex.width = 2;
  tex.height = 2;
  tex.channels = 3;
  tex.texels = {1.0f, 0.2f, 0.1f, 0.1f, 1.0f, 0.3f, 0.3f, 0.2f, 1.0f, 0.8f, 0.8f, 0.2f};
  s.textures.push_back(tex);
  s.lights[0].emission_texture = static_cast<int>(s.textures.size()) - 1;
  return s;
}

/// k×k samples of `pattern`; `seed` drives the random patterns (the grid has none).
inline LightSampleSpec sample_spec(SamplePattern pattern, int k, uint64_t seed = 1) {
  LightSampleSpec s;
  s.pattern = pattern;
  s.k = k;
  s.seed = seed;
  return s;
}

/// The regular k×k grid on the light.
inline LightSampleSpec grid_samples(int k) {
  return sample_spec(SamplePattern::grid, k);
}

/// One grid sample at the light centre: raytrace's hard shadow, the point the hard methods use.
inline LightSampleSpec centre_sample() {
  return grid_samples(1);
}

inline TestFrame make_test_frame(Scene scene, int width, int height, const LightSampleSpec& spec) {
  TestFrame t;
  scene.camera.width = width;
  scene.camera.height = height;
  t.scene = std::make_unique<Scene>(std::move(scene));
  t.frame = std::make_unique<Frame>(*t.scene, spec);
  return t;
}

inline TestFrame make_test_frame(const std::string& builtin, int width, int height,
                                 const LightSampleSpec& spec) {
  return make_test_frame(make_builtin_scene(builtin), width, height, spec);
}

}  // namespace penumbra::test
