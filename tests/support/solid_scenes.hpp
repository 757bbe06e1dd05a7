// The exact reference's closed-mesh test scene, shared by its culling and inner-ball tests: a
// sphere over a ground quad under a 1.2 × 0.9 rectangular light, in the variants that stress the
// solids (flipped inward, a hole, two overlapping spheres in one mesh, inconsistent orientation).
#pragma once

#include <utility>

#include "penumbra/scene/scene.hpp"
#include "penumbra/scene/shapes.hpp"

namespace penumbra::test {

struct SphereVariant {
  bool flipped = false;       // every triangle turned inward
  bool open = false;          // one triangle removed: a hole, closed by one cap triangle
  bool doubled = false;       // a second, overlapping sphere in the same mesh (self-intersecting)
  bool inconsistent = false;  // every third triangle flipped
  int rings = 12, sectors = 16;  // the sphere's tessellation (the doubled one's second: 10 × 14)
};

inline Scene sphere_over_ground(const SphereVariant& variant = {}) {
  Scene s;
  s.name = "solid-test";
  s.materials.push_back(Material{});
  Light l;
  l.shape = LightShape::rect;
  l.center = Vec3(0.1f, 2.5f, 0.0f);
  l.edge_u = Vec3(1.2f, 0.0f, 0.0f);
  l.edge_v = Vec3(0.0f, 0.0f, 0.9f);
  s.lights.push_back(l);
  Mesh sphere = make_sphere(Vec3(0.0f, 1.0f, 0.0f), 0.5f, variant.rings, variant.sectors);
  if (variant.doubled) {
    // Closed and consistently oriented but self-intersecting (winding number 2 in the overlap).
    const Mesh other = make_sphere(Vec3(0.3f, 1.1f, 0.1f), 0.45f, 10, 14);
    const uint32_t base = static_cast<uint32_t>(sphere.positions.size());
    sphere.positions.insert(sphere.positions.end(), other.positions.begin(), other.positions.end());
    for (Triangle t : other.triangles) {
      for (uint32_t& v : t.v) v += base;
      sphere.triangles.push_back(t);
    }
  }
  if (variant.flipped)
    for (Triangle& t : sphere.triangles) std::swap(t.v[1], t.v[2]);
  if (variant.inconsistent)
    for (size_t t = 0; t < sphere.triangles.size(); t += 3)
      std::swap(sphere.triangles[t].v[1], sphere.triangles[t].v[2]);
  if (variant.open) sphere.triangles.erase(sphere.triangles.begin() + 40);
  s.meshes.push_back(sphere);
  s.meshes.push_back(make_quad(Vec3(0.0f), Vec3(4.0f, 0.0f, 0.0f), Vec3(0.0f, 0.0f, -4.0f)));
  return s;
}

}  // namespace penumbra::test
