// Tests for the exact reference's back-face culling (ExactOptions::cull_back_faces): culled and
// unculled answers agree on closed, flipped (inward-facing), self-intersecting, open (capped) and
// inconsistently oriented meshes, for receivers outside, on and inside the solids; the culling path
// is really taken where it may be, and never where its premise (the light outside the solid's box)
// fails.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "penumbra/scene/builtin_scenes.hpp"
#include "penumbra/scene/model_paths.hpp"
#include "penumbra/scene/shapes.hpp"
#include "penumbra/shadows/exact/exact.hpp"

namespace penumbra {
namespace {

Scene sphere_scene(bool flipped, bool open, bool doubled) {
  Scene s;
  s.name = "culling-test";
  s.materials.push_back(Material{});
  Light l;
  l.shape = LightShape::rect;
  l.center = Vec3(0.1f, 2.5f, 0.0f);
  l.edge_u = Vec3(1.2f, 0.0f, 0.0f);
  l.edge_v = Vec3(0.0f, 0.0f, 0.9f);
  s.lights.push_back(l);
  Mesh sphere = make_sphere(Vec3(0.0f, 1.0f, 0.0f), 0.5f, 12, 16);
  if (doubled) {
    // One mesh, two overlapping spheres: closed and consistently oriented but self-intersecting
    // (winding number 2 where they overlap).
    const Mesh other = make_sphere(Vec3(0.3f, 1.1f, 0.1f), 0.45f, 10, 14);
    const uint32_t base = static_cast<uint32_t>(sphere.positions.size());
    sphere.positions.insert(sphere.positions.end(), other.positions.begin(), other.positions.end());
    for (Triangle t : other.triangles) {
      for (uint32_t& v : t.v) v += base;
      sphere.triangles.push_back(t);
    }
  }
  if (flipped)
    for (Triangle& t : sphere.triangles) std::swap(t.v[1], t.v[2]);
  if (open) sphere.triangles.erase(sphere.triangles.begin() + 40);
  s.meshes.push_back(sphere);
  s.meshes.push_back(make_quad(Vec3(0.0f), Vec3(4.0f, 0.0f, 0.0f), Vec3(0.0f, 0.0f, -4.0f)));
  return s;
}

/// Receivers on the ground, on the sphere (offset outward), inside it, inside its box but outside
/// it, and in the overlap of the doubled spheres.
std::vector<Vec3> receivers() {
  std::vector<Vec3> out;
  for (int i = 0; i < 9; ++i)
    for (int j = 0; j < 9; ++j) out.push_back(Vec3(-0.8f + 0.2f * i, 1e-4f, -0.8f + 0.2f * j));
  for (int k = 0; k < 24; ++k) {
    const float a = 0.26f * k, b = 0.13f * k;
    const Vec3 d(std::cos(a) * std::sin(b + 0.2f), std::cos(b + 0.2f), std::sin(a) * std::sin(b));
    out.push_back(Vec3(0.0f, 1.0f, 0.0f) + 0.5002f * glm::normalize(d));  // just outside
    out.push_back(Vec3(0.0f, 1.0f, 0.0f) + 0.3f * glm::normalize(d));     // inside
  }
  out.push_back(Vec3(0.45f, 1.45f, 0.45f));  // in the box, outside the sphere
  out.push_back(Vec3(0.2f, 1.05f, 0.05f));   // in both doubled spheres
  return out;
}

struct Agreement {
  double max_diff = 0.0;
  uint64_t culled = 0, shadowed = 0;
};

Agreement compare_culling(const Scene& s) {
  const ExactScene culled(s, 4, true), full(s, 4, false);
  const ExactLight light(s, s.lights[0]);
  Agreement a;
  for (const Vec3& p : receivers()) {
    const ExactPointResult c = exact_visibility(culled, light, p);
    const ExactPointResult f = exact_visibility(full, light, p);
    EXPECT_EQ(f.culled, 0u);
    a.max_diff = std::max(a.max_diff, std::abs(c.visible - f.visible));
    a.culled += c.culled;
    a.shadowed += f.visible < 1.0;
  }
  return a;
}

TEST(ExactCulling, ClosedSphereCulledEqualsUnculled) {
  const Agreement a = compare_culling(sphere_scene(false, false, false));
  std::printf("closed: max |culled - unculled| %.3g, %llu triangles culled\n", a.max_diff,
              static_cast<unsigned long long>(a.culled));
  EXPECT_LE(a.max_diff, 1e-9);  // measured 0: the same union, rounded to the same integers
  EXPECT_GT(a.culled, 1000u);
  EXPECT_GT(a.shadowed, 40u);
}

TEST(ExactCulling, FlippedSphereCulledEqualsUnculled) {
  // Inward-facing triangles: the kept set is the far side, still exact.
  const Agreement a = compare_culling(sphere_scene(true, false, false));
  EXPECT_LE(a.max_diff, 1e-9);
  EXPECT_GT(a.culled, 1000u);
}

TEST(ExactCulling, SelfIntersectingClosedMeshCulledEqualsUnculled) {
  const Agreement a = compare_culling(sphere_scene(false, false, true));
  EXPECT_LE(a.max_diff, 1e-9);
  EXPECT_GT(a.culled, 1000u);
}

TEST(ExactCulling, OpenMeshClosedByCapsCulledEqualsUnculled) {
  // A sphere with a hole: its cap is one triangle; pixels whose pyramid meets it keep every
  // triangle.
  const Scene s = sphere_scene(false, true, false);
  const ExactScene es(s);
  ASSERT_EQ(es.solids().size(), 2u);  // the sphere and the ground quad
  EXPECT_EQ(es.solids()[0].caps.size(), 1u);
  const Agreement a = compare_culling(s);
  EXPECT_LE(a.max_diff, 1e-9);
  EXPECT_GT(a.culled, 1000u);
}

TEST(ExactCulling, InconsistentlyOrientedMeshCulledEqualsUnculled) {
  // Every third triangle flipped: the caps close the chain over the inconsistent edges.
  Scene s = sphere_scene(false, false, false);
  for (size_t t = 0; t < s.meshes[0].triangles.size(); t += 3)
    std::swap(s.meshes[0].triangles[t].v[1], s.meshes[0].triangles[t].v[2]);
  const Agreement a = compare_culling(s);
  EXPECT_LE(a.max_diff, 1e-9);
}

TEST(ExactCulling, LightOverlappingTheSolidsBoxDisablesIt) {
  Scene s = sphere_scene(false, false, false);
  s.lights[0].center = Vec3(0.0f, 1.4f, 0.0f);  // inside the sphere's box (and the sphere)
  const ExactScene es(s);
  const ExactLight light(s, s.lights[0]);
  for (const Vec3& p : receivers()) EXPECT_EQ(exact_visibility(es, light, p).culled, 0u);
}

TEST(ExactCulling, BuiltinScenesCulledEqualsUnculled) {
  for (const char* name : {"spheres", "default", "bunny"}) {
    if (std::string(name) == "bunny" && !find_model("bunny00.off")) continue;  // model optional
    const Scene s = make_builtin_scene(name);
    const ExactScene culled(s, 4, true), full(s, 4, false);
    const ExactLight light(s, s.lights[0]);
    const Bounds3 b = s.bounds();
    double worst = 0.0;
    for (int i = 0; i < 12; ++i)
      for (int j = 0; j < 12; ++j) {
        const Vec3 p(b.lo.x + (i + 0.5f) / 12 * (b.hi.x - b.lo.x), b.lo.y + 1e-3f * b.diagonal(),
                     b.lo.z + (j + 0.5f) / 12 * (b.hi.z - b.lo.z));
        worst = std::max(worst, std::abs(exact_visibility(culled, light, p).visible -
                                         exact_visibility(full, light, p).visible));
      }
    EXPECT_LE(worst, 1e-9) << name;
  }
}

}  // namespace
}  // namespace penumbra
