// Tests for the exact reference's inner balls (shadows/exact/solid_interior.hpp): every ball misses
// its solid's surface and caps and has a non-zero winding number, checked by independent brute
// force (point–triangle distances by plane and edge projections, winding numbers by solid angles);
// receivers the balls put in umbra are blocked toward every one of 1024 light points by brute
// force, on closed, flipped, self-intersecting, open and inconsistently oriented meshes and the
// built-in scenes.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <string>
#include <vector>

#include "penumbra/scene/builtin_scenes.hpp"
#include "penumbra/scene/model_paths.hpp"
#include "penumbra/scene/shapes.hpp"
#include "penumbra/shadows/exact/exact.hpp"
#include "penumbra/shadows/exact/solid_interior.hpp"
#include "support/frame_helpers.hpp"
#include "support/solid_scenes.hpp"

namespace penumbra {
namespace {

double segment_distance(const DVec3& p, const DVec3& a, const DVec3& b) {
  const DVec3 ab = b - a;
  const double t = std::clamp(glm::dot(p - a, ab) / glm::dot(ab, ab), 0.0, 1.0);
  return glm::length(p - (a + t * ab));
}

/// Distance from p to triangle (a, b, c): to its plane where p projects inside, else to its edges.
double triangle_distance(const DVec3& p, const DVec3& a, const DVec3& b, const DVec3& c) {
  const DVec3 n = glm::normalize(glm::cross(b - a, c - a));
  const DVec3 f = p - glm::dot(p - a, n) * n;  // foot on the plane
  const bool inside = glm::dot(glm::cross(b - a, f - a), n) >= 0.0 &&
                      glm::dot(glm::cross(c - b, f - b), n) >= 0.0 &&
                      glm::dot(glm::cross(a - c, f - c), n) >= 0.0;
  if (inside) return std::abs(glm::dot(p - a, n));
  return std::min(
      {segment_distance(p, a, b), segment_distance(p, b, c), segment_distance(p, c, a)});
}

/// The signed solid angle of triangle (a, b, c) seen from p [Van Oosterom 1983], over 4π.
double winding_part(const DVec3& p, const DVec3& a0, const DVec3& b0, const DVec3& c0) {
  const DVec3 a = a0 - p, b = b0 - p, c = c0 - p;
  const double la = glm::length(a), lb = glm::length(b), lc = glm::length(c);
  const double num = glm::dot(a, glm::cross(b, c));
  const double den = la * lb * lc + glm::dot(a, b) * lc + glm::dot(a, c) * lb + glm::dot(b, c) * la;
  return 2.0 * std::atan2(num, den) / (4.0 * std::numbers::pi);
}

/// The solid's triangles (its mesh, zero-area ones included) and its caps.
std::vector<std::array<DVec3, 3>> solid_triangles(const Scene& s, const ExactSolid& solid) {
  std::vector<std::array<DVec3, 3>> out(solid.caps.begin(), solid.caps.end());
  const Mesh& m = s.meshes[solid.mesh];
  for (size_t t = 0; t < m.triangle_count(); ++t)
    out.push_back({DVec3(m.vertex(t, 0)), DVec3(m.vertex(t, 1)), DVec3(m.vertex(t, 2))});
  return out;
}

struct BallCheck {
  size_t balls = 0;
  double worst_clearance = 1e300;  // min over balls of (distance to surface − radius) / radius
  double worst_winding_rounding = 0.0;
  double largest = 0.0;
};

/// Every ball of every solid against brute force.
BallCheck check_balls(const Scene& s) {
  const ExactScene es(s);
  BallCheck r;
  for (const ExactSolid& solid : es.solids()) {
    // The groups partition the balls in order, each bound holding its members.
    uint32_t next = 0;
    for (const ExactBallGroup& g : solid.ball_groups) {
      EXPECT_EQ(g.first, next);
      EXPECT_GE(g.count, 1u);
      next = g.first + g.count;
      for (uint32_t k = g.first; k < next; ++k)
        EXPECT_LE(glm::length(solid.balls[k].center - g.bound.center) + solid.balls[k].radius,
                  g.bound.radius);
    }
    EXPECT_EQ(next, solid.balls.size());
    const auto tris = solid_triangles(s, solid);
    for (size_t k = 0; k < solid.balls.size(); ++k) {
      const ExactInnerBall& b = solid.balls[k];
      double d = 1e300, w = 0.0;
      for (const auto& t : tris) {
        d = std::min(d, triangle_distance(b.center, t[0], t[1], t[2]));
        w += winding_part(b.center, t[0], t[1], t[2]);
      }
      EXPECT_GT(d, b.radius);
      EXPECT_NE(std::lround(w), 0);
      r.worst_clearance = std::min(r.worst_clearance, (d - b.radius) / b.radius);
      r.worst_winding_rounding = std::max(r.worst_winding_rounding, std::abs(w - std::round(w)));
      r.largest = std::max(r.largest, b.radius);
      ++r.balls;
    }
  }
  return r;
}

TEST(ExactInnerBalls, ClosedSphereHoldsItsInscribedBall) {
  const Scene s = test::sphere_over_ground({});
  const BallCheck c = check_balls(s);
  // The polyhedron's inscribed radius: the nearest face plane from the centre.
  const Mesh& m = s.meshes[0];
  double inscribed = 1e300;
  for (size_t t = 0; t < m.triangle_count(); ++t)
    inscribed =
        std::min(inscribed, triangle_distance(DVec3(0, 1, 0), DVec3(m.vertex(t, 0)),
                                              DVec3(m.vertex(t, 1)), DVec3(m.vertex(t, 2))));
  std::printf("closed sphere: %zu balls, largest %.5f of inscribed %.5f, clearance %.3g\n", c.balls,
              c.largest, inscribed, c.worst_clearance);
  ASSERT_GE(c.balls, 1u);
  EXPECT_LE(c.largest, inscribed);
  // The best voxel centre is √3/2 of a voxel (1/48 of the box) from the sphere's: 0.468.
  EXPECT_GE(c.largest, 0.965 * inscribed);  // measured 0.4703
  EXPECT_GE(c.worst_clearance, 0.9e-6);     // the radius margin, nothing eaten by rounding
  EXPECT_LE(c.worst_winding_rounding, 1e-9);
}

TEST(ExactInnerBalls, FlippedSelfIntersectingOpenAndInconsistentMeshes) {
  // Smallest largest ball expected. The doubled spheres' surfaces cross inside each other; the
  // inconsistent sphere's caps (fans over its non-cancelling edges) cut through its inside, so it
  // may have none: every ball found must still pass the brute force.
  const struct {
    const char* name;
    Scene scene;
    double largest;
  } cases[] = {{"flipped", test::sphere_over_ground({.flipped = true}), 0.47},
               {"self-intersecting", test::sphere_over_ground({.doubled = true}), 0.28},
               {"open (capped)", test::sphere_over_ground({.open = true}), 0.47},
               {"inconsistent", test::sphere_over_ground({.inconsistent = true}), 0.0}};
  for (const auto& k : cases) {
    const BallCheck c = check_balls(k.scene);
    std::printf("%s: %zu balls, largest %.4f\n", k.name, c.balls, c.largest);
    EXPECT_GE(c.largest, k.largest) << k.name;  // measured 0.4703, 0.2877, 0.4703, 0
    if (c.balls > 0) {
      EXPECT_GE(c.worst_clearance, 0.9e-6) << k.name;
    }
  }
}

TEST(ExactInnerBalls, OpenSurfacesAndFlatMeshesHaveNone) {
  // The ground quad is a solid (closed by its caps) with no volume: no ball.
  const Scene s = test::sphere_over_ground({});
  const ExactScene es(s);
  ASSERT_EQ(es.solids().size(), 2u);
  EXPECT_TRUE(es.solids()[1].balls.empty());
}

TEST(ExactInnerBalls, BuiltinScenesBallsMissTheSurface) {
  for (const char* name : {"spheres", "default", "bunny", "dragon"}) {
    if ((std::string(name) == "bunny" && !find_model("bunny00.off")) ||
        (std::string(name) == "dragon" && !find_model("ChineseDragon-10kv.off")))
      continue;  // models optional
    const BallCheck c = check_balls(make_builtin_scene(name));
    std::printf("%s: %zu balls, largest %.4f, clearance %.3g\n", name, c.balls, c.largest,
                c.worst_clearance);
    EXPECT_GE(c.balls, 1u) << name;
    EXPECT_GE(c.worst_clearance, 0.9e-6) << name;
  }
}

TEST(ExactInnerBalls, ManySolidsShareOneBudget) {
  // 3 000 closed boxes and one sphere, each its own mesh: the sphere (most triangles) is served
  // first, and the boxes together measure no more than the frame's budget.
  Scene s = test::sphere_over_ground({});
  for (int k = 0; k < 3000; ++k)
    s.meshes.push_back(
        make_box(Vec3(-3.0f + 0.1f * (k % 60), 0.3f, -3.0f + 0.1f * (k / 60)), Vec3(0.03f)));
  const auto start = std::chrono::steady_clock::now();
  const ExactScene es(s);
  const double ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  size_t balls = 0, boxes_with_balls = 0;
  for (const ExactSolid& solid : es.solids()) {
    balls += solid.balls.size();
    boxes_with_balls += solid.mesh >= 2 && !solid.balls.empty() ? 1 : 0;
  }
  std::printf("%zu solids: %zu balls (%zu boxes with some), set-up %.0f ms\n", es.solids().size(),
              balls, boxes_with_balls, ms);
  ASSERT_EQ(es.solids().size(), 3002u);
  EXPECT_GE(es.solids()[0].balls.size(), 1u);  // the sphere
  EXPECT_LE(balls, kInnerBallBudget);          // every kept ball was measured
  EXPECT_LT(boxes_with_balls, 3000u);          // the budget ran out before the last boxes
  for (size_t k = 2; k < es.solids().size(); ++k) EXPECT_LE(es.solids()[k].balls.size(), 12u);
}

/// Receivers in rows over the ground (each row with its hint, as the method runs them): those the
/// balls put in umbra must be blocked toward all 32 × 32 light points by brute force over every
/// triangle; with and without hints the answers agree; the result of the ball path agrees with the
/// same scene without solids (every triangle projected) to 1e-9.
struct UmbraCheck {
  size_t by_ball = 0, umbra = 0, unblocked = 0;
  double max_diff = 0.0;
};

UmbraCheck check_umbra(const Scene& s, const std::vector<std::vector<Vec3>>& rows) {
  const ExactScene culled(s), full(s, 4, false);
  const ExactLight light(s, s.lights[0]);
  UmbraCheck r;
  for (const auto& row : rows) {
    ExactUmbraHint hint;
    for (const Vec3& p : row) {
      const ExactPointResult hinted = exact_visibility(culled, light, p, &hint);
      const ExactPointResult plain = exact_visibility(culled, light, p);
      const ExactPointResult unculled = exact_visibility(full, light, p);
      EXPECT_FALSE(unculled.umbra_by_ball);
      r.max_diff = std::max({r.max_diff, std::abs(hinted.visible - unculled.visible),
                             std::abs(plain.visible - unculled.visible)});
      r.umbra += unculled.visible <= 1e-9 ? 1 : 0;
      if (!hinted.umbra_by_ball) continue;
      ++r.by_ball;
      const LightFrame f = light_frame(s.lights[0], p);
      constexpr int k = 32;
      for (int i = 0; i < k; ++i)
        for (int j = 0; j < k; ++j) {
          const DVec3 q = DVec3(f.corner) + ((i + 0.5) / k) * DVec3(f.edge_u) +
                          ((j + 0.5) / k) * DVec3(f.edge_v);
          bool blocked = false;
          for (const Mesh& m : s.meshes)
            for (size_t t = 0; t < m.triangle_count() && !blocked; ++t)
              blocked =
                  test::segment_crosses_triangle(DVec3(p), q - DVec3(p), DVec3(m.vertex(t, 0)),
                                                 DVec3(m.vertex(t, 1)), DVec3(m.vertex(t, 2)));
          r.unblocked += blocked ? 0 : 1;
        }
    }
  }
  return r;
}

std::vector<std::vector<Vec3>> ground_rows(float half, int n) {
  std::vector<std::vector<Vec3>> rows(n);
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i)
      rows[j].push_back(
          Vec3(-half + 2 * half * (i + 0.5f) / n, 1e-4f, -half + 2 * half * (j + 0.5f) / n));
  return rows;
}

TEST(ExactInnerBalls, UmbraByBallsIsBlockedEverywhere) {
  // The smallest share of the umbra receivers the balls are expected to decide.
  const struct {
    const char* name;
    Scene scene;
    double share;
  } cases[] = {{"closed", test::sphere_over_ground({}), 0.75},
               {"flipped", test::sphere_over_ground({.flipped = true}), 0.75},
               {"self-intersecting", test::sphere_over_ground({.doubled = true}), 0.35},
               {"open (capped)", test::sphere_over_ground({.open = true}), 0.6},
               {"inconsistent", test::sphere_over_ground({.inconsistent = true}), 0.0}};
  for (const auto& k : cases) {
    const UmbraCheck c = check_umbra(k.scene, ground_rows(0.6f, 16));
    std::printf("%s: %zu of %zu umbra receivers by balls, max |diff| %.3g\n", k.name, c.by_ball,
                c.umbra, c.max_diff);
    // Measured 56/70, 56/70, 43/115, 47/70, 0/70.
    EXPECT_GE(static_cast<double>(c.by_ball), k.share * static_cast<double>(c.umbra)) << k.name;
    EXPECT_EQ(c.unblocked, 0u) << k.name;
    EXPECT_LE(c.max_diff, 1e-9) << k.name;  // measured 1.1e-16
  }
}

TEST(ExactInnerBalls, PremisesFailingKeepsTheProjection) {
  // The light inside the sphere's box: w = 0 on the light is not established, no ball is used.
  Scene s = test::sphere_over_ground({});
  s.lights[0].center = Vec3(0.0f, 1.4f, 0.0f);
  const UmbraCheck inside = check_umbra(s, ground_rows(0.6f, 8));
  EXPECT_EQ(inside.by_ball, 0u);
  // A light far larger than the sphere: no ball hides it from the ground (the sphere's umbra is
  // gone), and every answer agrees with the full projection.
  Scene wide = test::sphere_over_ground({});
  wide.lights[0].edge_u = Vec3(8.0f, 0.0f, 0.0f);
  wide.lights[0].edge_v = Vec3(0.0f, 0.0f, 8.0f);
  const UmbraCheck w = check_umbra(wide, ground_rows(0.6f, 8));
  EXPECT_EQ(w.by_ball, 0u);
  EXPECT_LE(w.max_diff, 1e-9);
}

TEST(ExactInnerBalls, EveryLightShape) {
  // Disk and sphere lights (round outlines inside the parallelogram the balls are tested
  // against): the same agreement with the full projection.
  for (const LightShape shape : {LightShape::disk, LightShape::sphere}) {
    Scene s = test::sphere_over_ground({});
    s.lights[0].shape = shape;
    s.lights[0].radius = 0.4f;
    const UmbraCheck c = check_umbra(s, ground_rows(0.6f, 12));
    std::printf("shape %d: %zu of %zu umbra receivers by balls, max |diff| %.3g\n",
                static_cast<int>(shape), c.by_ball, c.umbra, c.max_diff);
    EXPECT_GE(c.by_ball, c.umbra / 2);  // measured 58 of 98 for both
    EXPECT_EQ(c.unblocked, 0u);
    EXPECT_LE(c.max_diff, 1e-9);  // measured 0
  }
}

}  // namespace
}  // namespace penumbra
