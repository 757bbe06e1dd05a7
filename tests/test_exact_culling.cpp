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
#include "support/solid_scenes.hpp"

namespace penumbra {
namespace {

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
  const Agreement a = compare_culling(test::sphere_over_ground({}));
  std::printf("closed: max |culled - unculled| %.3g, %llu triangles culled\n", a.max_diff,
              static_cast<unsigned long long>(a.culled));
  EXPECT_LE(a.max_diff, 1e-9);  // measured 0: the same union, rounded to the same integers
  EXPECT_GT(a.culled, 1000u);
  EXPECT_GT(a.shadowed, 40u);
}

TEST(ExactCulling, FlippedSphereCulledEqualsUnculled) {
  // Inward-facing triangles: the kept set is the far side, still exact.
  const Agreement a = compare_culling(test::sphere_over_ground({.flipped = true}));
  EXPECT_LE(a.max_diff, 1e-9);
  EXPECT_GT(a.culled, 1000u);
}

TEST(ExactCulling, SelfIntersectingClosedMeshCulledEqualsUnculled) {
  const Agreement a = compare_culling(test::sphere_over_ground({.doubled = true}));
  EXPECT_LE(a.max_diff, 1e-9);
  EXPECT_GT(a.culled, 1000u);
}

TEST(ExactCulling, OpenMeshClosedByCapsCulledEqualsUnculled) {
  // A sphere with a hole: its cap is one triangle; pixels whose pyramid meets it keep every
  // triangle.
  const Scene s = test::sphere_over_ground({.open = true});
  const ExactScene es(s);
  ASSERT_EQ(es.solids().size(), 2u);  // the sphere and the ground quad
  EXPECT_EQ(es.solids()[0].caps.size(), 1u);
  const Agreement a = compare_culling(s);
  EXPECT_LE(a.max_diff, 1e-9);
  EXPECT_GT(a.culled, 1000u);
}

TEST(ExactCulling, InconsistentlyOrientedMeshCulledEqualsUnculled) {
  // Every third triangle flipped: the caps close the chain over the inconsistent edges.
  const Scene s = test::sphere_over_ground({.inconsistent = true});
  const Agreement a = compare_culling(s);
  EXPECT_LE(a.max_diff, 1e-9);
}

TEST(ExactCulling, LightOverlappingTheSolidsBoxDisablesIt) {
  Scene s = test::sphere_over_ground({});
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
