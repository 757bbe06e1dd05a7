// Small scenes that once exposed defects or document known limits (review and fuzzing), built in
// code: curved open sheets (a bowl), a closed sphere with one flipped triangle, occluders touching
// or containing the light, and the wedge methods' measured artefact cases. Meshes are generated
// here rather than committed.
#pragma once

#include <cmath>
#include <utility>
#include <vector>

#include "penumbra/scene/builtin_scenes.hpp"
#include "penumbra/scene/shapes.hpp"

namespace penumbra::test {

/// A UV hemisphere bowl open at the top (`closed` = false: rings bands from the rim at y = cy
/// down to the bottom pole) or a full UV sphere (`closed`: 2·rings bands), radius r, centred on
/// (0, cy, 0), every face wound outward, the pole triangles that collapse dropped. `flip_one`
/// reverses the winding of the face at a third of the list (one inconsistently oriented
/// triangle in a closed mesh).
inline Mesh make_bowl(int rings, int segments, float r, float cy, bool closed = false,
                      bool flip_one = false) {
  constexpr double kPi = 3.14159265358979323846;
  Mesh m;
  m.name = closed ? "sphere" : "bowl";
  const int bands = closed ? 2 * rings : rings;
  for (int i = 0; i <= bands; ++i) {
    const double th = closed ? kPi * i / bands : kPi / 2 + (kPi / 2) * i / bands;
    const double st = std::abs(std::sin(th)) < 1e-12 ? 0.0 : std::sin(th);
    for (int j = 0; j < segments; ++j) {
      const double ph = 2 * kPi * j / segments;
      m.positions.push_back(Vec3(static_cast<float>(r * st * std::cos(ph)),
                                 static_cast<float>(cy + r * std::cos(th)),
                                 static_cast<float>(r * st * std::sin(ph))));
    }
  }
  auto idx = [&](int i, int j) { return static_cast<uint32_t>(i * segments + (j % segments)); };
  for (int i = 0; i < bands; ++i) {
    for (int j = 0; j < segments; ++j) {
      const uint32_t a = idx(i, j), b = idx(i, j + 1), c = idx(i + 1, j), d = idx(i + 1, j + 1);
      for (Triangle t : {Triangle{{a, c, b}}, Triangle{{b, c, d}}}) {
        const DVec3 p0(m.positions[t.v[0]]), p1(m.positions[t.v[1]]), p2(m.positions[t.v[2]]);
        if (p0 == p1 || p1 == p2 || p0 == p2) continue;  // collapsed at a pole
        const DVec3 mid = (p0 + p1 + p2) / 3.0 - DVec3(0.0, cy, 0.0);
        if (glm::dot(glm::cross(p1 - p0, p2 - p0), mid) < 0.0) std::swap(t.v[1], t.v[2]);
        m.triangles.push_back(t);
      }
    }
  }
  if (flip_one)
    std::swap(m.triangles[m.triangles.size() / 3].v[1], m.triangles[m.triangles.size() / 3].v[2]);
  return m;
}

/// An open half-cylinder "tunnel" of radius r along z (length len), its axis at height cy: a
/// curved open sheet with a large boundary (two arcs, two straight edges).
inline Mesh make_half_cylinder(int segments, float r, float cy, float len) {
  constexpr double kPi = 3.14159265358979323846;
  Mesh m;
  m.name = "half_cylinder";
  for (int j = 0; j <= segments; ++j) {
    const double ph = kPi * j / segments;
    for (float z : {-0.5f * len, 0.5f * len})
      m.positions.push_back(
          Vec3(static_cast<float>(r * std::cos(ph)), static_cast<float>(cy + r * std::sin(ph)), z));
  }
  for (uint32_t j = 0; j < static_cast<uint32_t>(segments); ++j) {
    const uint32_t a = 2 * j, b = a + 1, c = a + 2, d = a + 3;
    m.triangles.push_back({{a, b, c}});
    m.triangles.push_back({{c, b, d}});
  }
  return m;
}

/// The 10 × 10 ground, `occluders`, a square rect light of side `light_side` at `light_centre`
/// facing down, the camera at `eye` looking at `target`.
inline Scene ground_scene(std::vector<Mesh> occluders, const Vec3& light_centre, float light_side,
                          const Vec3& eye, const Vec3& target, float vfov_deg = 45.0f) {
  Scene s = make_builtin_scene("quad");
  const int material = s.meshes[1].material;
  s.meshes.resize(1);
  for (Mesh& m : occluders) {
    m.material = material;
    s.meshes.push_back(std::move(m));
  }
  Light& l = s.lights[0];
  l.center = light_centre;
  l.edge_u = Vec3(light_side, 0.0f, 0.0f);
  l.edge_v = Vec3(0.0f, 0.0f, light_side);
  s.camera.position = eye;
  s.camera.target = target;
  s.camera.vfov_deg = vfov_deg;
  return s;
}

/// The ground-and-one-mesh scene the bowl and sphere cases use: the 10 × 10 ground, `mesh`, a
/// 0.8 × 0.8 rect light at (−0.9, 3, 0.2) facing down, the camera above and in front.
inline Scene bowl_scene(Mesh mesh) {
  std::vector<Mesh> m;
  m.push_back(std::move(mesh));
  return ground_scene(std::move(m), Vec3(-0.9f, 3.0f, 0.2f), 0.8f, Vec3(0.0f, 3.2f, 2.6f),
                      Vec3(0.4f, 0.0f, 0.0f));
}

/// A vertical wall (x = 0.2, y ∈ [1, 4], z ∈ [−½, ½]) through the plane of a 0.8 × 0.8 light at
/// (0, 3, 0), 0.2 off its centre: the occluder cuts the light in two.
inline Scene wall_through_light_scene() {
  std::vector<Mesh> m;
  m.push_back(make_quad(Vec3(0.2f, 2.5f, 0.0f), Vec3(0, 3, 0), Vec3(0, 0, 1)));
  return ground_scene(std::move(m), Vec3(0.0f, 3.0f, 0.0f), 0.8f, Vec3(0.0f, 3.2f, 3.2f),
                      Vec3(0.3f, 0.0f, 0.0f), 50.0f);
}

/// Two disjoint coplanar bars at y = 1 (x = ±0.2, 0.25 wide, 1.2 long) under a 1 × 1 light at
/// y = 2: their shadows meet and their silhouette loops' coverages add exactly.
inline Scene coplanar_bars_scene() {
  std::vector<Mesh> m;
  for (float x : {-0.2f, 0.2f})
    m.push_back(make_quad(Vec3(x, 1.0f, 0.0f), Vec3(0, 0, 1.2f), Vec3(0.25f, 0, 0)));
  return ground_scene(std::move(m), Vec3(0.0f, 2.0f, 0.0f), 1.0f, Vec3(0.0f, 3.0f, 2.6f),
                      Vec3(0.0f));
}

/// A 0.5 × 0.7 × 0.5 box on the ground under a large close 1.2 × 1.2 light at y = 1.2: the
/// silhouette from the light centre is far from the silhouette from the light's corners.
inline Scene box_under_close_light_scene() {
  std::vector<Mesh> m;
  m.push_back(make_box(Vec3(0.0f, 0.35f, 0.0f), Vec3(0.25f, 0.35f, 0.25f)));
  return ground_scene(std::move(m), Vec3(0.0f, 1.2f, 0.0f), 1.2f, Vec3(2.2f, 2.4f, 3.2f),
                      Vec3(0.0f, 0.4f, 0.1f));
}

/// A 6 × 6 ground, one box (centre, half extent) and a light at `light_centre`: a 1 × 1 rect
/// facing down, or a point light. The camera looks down at the box from the front right.
inline Scene box_scene(const Vec3& box_centre, const Vec3& half_extent, const Vec3& light_centre,
                       LightShape shape = LightShape::rect) {
  Scene s = make_builtin_scene("quad");
  s.meshes[0] = make_quad(Vec3(0.0f), Vec3(0, 0, 6), Vec3(6, 0, 0));
  s.meshes[0].material = 0;
  s.meshes[1] = make_box(box_centre, half_extent);
  s.meshes[1].material = 0;
  Light& l = s.lights[0];
  l.shape = shape;
  l.center = light_centre;
  l.edge_u = Vec3(1.0f, 0.0f, 0.0f);
  l.edge_v = Vec3(0.0f, 0.0f, 1.0f);
  s.camera.position = Vec3(2.5f, 4.0f, 5.0f);
  s.camera.target = Vec3(0.0f, 0.3f, 0.0f);
  return s;
}

}  // namespace penumbra::test
