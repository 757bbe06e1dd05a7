// Tests for the exact reference's edge trees (ExactOptions::edge_trees, edge_tree.hpp): the
// silhouette of a large solid found from a hierarchy over its edges, closed along the light's
// left side by one counting ray, gives the same V as visiting its faces — on closed, flipped,
// open (capped), self-intersecting, inconsistently oriented and non-manifold meshes, for receivers
// on the ground, on the mesh, inside it and inside its box, under a light the mesh nearly touches;
// the path is really taken, and a silhouette along the light's side falls back to the faces; and
// perforated occluders with many edges (the divided sweep's groups) on the garden.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include "penumbra/render/receivers.hpp"
#include "penumbra/scene/builtin_scenes.hpp"
#include "penumbra/scene/shapes.hpp"
#include "penumbra/shadows/exact/exact.hpp"
#include "support/frame_helpers.hpp"
#include "support/solid_scenes.hpp"

namespace penumbra {
namespace {

/// Receivers on the ground under and around the sphere, on it (just outside), inside it, and in
/// its box outside it.
std::vector<Vec3> receivers() {
  std::vector<Vec3> out;
  for (int i = 0; i < 15; ++i)
    for (int j = 0; j < 15; ++j) out.push_back(Vec3(-1.4f + 0.2f * i, 1e-4f, -1.4f + 0.2f * j));
  for (int k = 0; k < 40; ++k) {
    const float a = 0.26f * k, b = 0.077f * k;
    const Vec3 d(std::cos(a) * std::sin(b + 0.2f), std::cos(b + 0.2f), std::sin(a) * std::sin(b));
    out.push_back(Vec3(0.0f, 1.0f, 0.0f) + 0.5003f * glm::normalize(d));  // just outside
    out.push_back(Vec3(0.0f, 1.0f, 0.0f) + 0.3f * glm::normalize(d));     // inside
  }
  out.push_back(Vec3(0.45f, 1.45f, 0.45f));  // in the box, outside the sphere
  return out;
}

struct Agreement {
  double max_diff = 0.0;
  uint64_t by_edges = 0, fallbacks = 0, shadowed = 0, penumbra = 0;
};

/// V with edge trees against V by the faces, per receiver (both with back-face culling).
Agreement compare_edge_trees(const Scene& s) {
  const ExactScene edges(s, 8, true, true), faces(s, 8, true, false);
  EXPECT_EQ(faces.edge_trees().size(), 0u);
  const ExactLight light(s, s.lights[0]);
  Agreement a;
  for (const Vec3& p : receivers()) {
    const ExactPointResult e = exact_visibility(edges, light, p);
    const ExactPointResult f = exact_visibility(faces, light, p);
    EXPECT_EQ(f.edge_tree_solids, 0u);
    a.max_diff = std::max(a.max_diff, std::abs(e.visible - f.visible));
    a.by_edges += e.edge_tree_solids;
    a.fallbacks += e.edge_tree_fallbacks;
    a.shadowed += f.visible < 1.0 ? 1 : 0;
    a.penumbra += f.visible < 1.0 && f.visible > 0.0 ? 1 : 0;
  }
  std::printf(
      "max |dV| %.3g, %llu receivers by edge trees, %llu fallbacks, %llu shadowed, %llu "
      "in penumbra\n",
      a.max_diff, static_cast<unsigned long long>(a.by_edges),
      static_cast<unsigned long long>(a.fallbacks), static_cast<unsigned long long>(a.shadowed),
      static_cast<unsigned long long>(a.penumbra));
  return a;
}

/// The solid-test sphere with enough triangles for an edge tree.
test::SphereVariant fine(test::SphereVariant v) {
  v.rings = 32;
  v.sectors = 48;
  return v;
}

// The faces' path clips triangles straddling the pyramid to Clipper's integer grid (≈ 1e-9 of the
// light); the edge trees' path is in double throughout: they agree to that grid.
constexpr double kGrid = 2e-9;

TEST(ExactEdgeTrees, ClosedSphereAgreesWithTheFaces) {
  const Agreement a = compare_edge_trees(test::sphere_over_ground(fine({})));
  EXPECT_LE(a.max_diff, kGrid);
  EXPECT_GT(a.by_edges, 250u);  // ground and on-sphere receivers take the edge path
  EXPECT_GT(a.penumbra, 60u);
  EXPECT_EQ(a.fallbacks, 0u);
}

TEST(ExactEdgeTrees, FlippedOpenDoubledAndInconsistentSpheres) {
  for (const test::SphereVariant v :
       {test::SphereVariant{.flipped = true}, test::SphereVariant{.open = true},
        test::SphereVariant{.doubled = true}, test::SphereVariant{.inconsistent = true}}) {
    const Agreement a = compare_edge_trees(test::sphere_over_ground(fine(v)));
    EXPECT_LE(a.max_diff, kGrid);
    EXPECT_GT(a.penumbra, 60u);
  }
}

TEST(ExactEdgeTrees, NonManifoldFinsAreBoundaryEdges) {
  // Three triangles on each of a few of the sphere's edges: those edges have no neighbour (never
  // cancel) and their cones are none.
  Scene s = test::sphere_over_ground(fine({}));
  Mesh& sphere = s.meshes[0];
  for (size_t t = 0; t < 40; t += 7) {
    const Triangle base = sphere.triangles[t];
    const Vec3 a = sphere.positions[base.v[0]], b = sphere.positions[base.v[1]];
    const Vec3 tip = 0.5f * (a + b) + 0.2f * glm::normalize(0.5f * (a + b) - Vec3(0, 1, 0));
    sphere.positions.push_back(tip);
    sphere.triangles.push_back(
        {{base.v[0], base.v[1], static_cast<uint32_t>(sphere.positions.size() - 1)}});
  }
  const Agreement a = compare_edge_trees(s);
  EXPECT_LE(a.max_diff, kGrid);
  // Fewer than on the closed sphere: the fins' caps put the pyramids that meet them on the faces.
  EXPECT_GT(a.by_edges, 80u);
}

TEST(ExactEdgeTrees, SphereNearTheLightKeepsTheFaces) {
  // The sphere's top 1e-3 below the light's plane, under its edge: kept faces reach the far end
  // of the segments of some receivers, which then visit the faces (or fall back), still equal.
  Scene s = test::sphere_over_ground(fine({}));
  s.lights[0].center = Vec3(0.7f, 1.501f, 0.0f);
  const Agreement a = compare_edge_trees(s);
  EXPECT_LE(a.max_diff, kGrid);
}

/// A box from `lo` to `hi` with every face an n × n grid of quads (outward, 12·n² triangles),
/// the shared rows computed by one expression so that the faces weld.
Mesh grid_box(const Vec3& lo, const Vec3& hi, int n) {
  Mesh m;
  const auto at = [&](int axis, int i) {
    return lo[axis] + (hi[axis] - lo[axis]) * static_cast<float>(i) / static_cast<float>(n);
  };
  for (int axis = 0; axis < 3; ++axis) {
    const int u = (axis + 1) % 3, v = (axis + 2) % 3;
    for (int side = 0; side < 2; ++side) {
      const uint32_t base = static_cast<uint32_t>(m.positions.size());
      for (int j = 0; j <= n; ++j)
        for (int i = 0; i <= n; ++i) {
          Vec3 p;
          p[axis] = side == 0 ? lo[axis] : hi[axis];
          p[u] = at(u, i);
          p[v] = at(v, j);
          m.positions.push_back(p);
        }
      for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
          const uint32_t a = base + static_cast<uint32_t>(j * (n + 1) + i), b = a + 1,
                         c = a + static_cast<uint32_t>(n + 1), d = c + 1;
          // (u, v, axis) is right-handed: a → b → d turns about +axis; reversed on the low side.
          if (side == 1) {
            m.triangles.push_back({{a, b, d}});
            m.triangles.push_back({{a, d, c}});
          } else {
            m.triangles.push_back({{a, d, b}});
            m.triangles.push_back({{a, c, d}});
          }
        }
    }
  }
  return m;
}

TEST(ExactEdgeTrees, SilhouetteAlongTheLightsSideFallsBackToTheFaces) {
  // The receiver lies in the plane x = 0 of the box's side face and of the light's u = 0 edge:
  // the box's bottom edges on x = 0 are silhouette edges running along the square's left side,
  // where the count cannot be stepped — that receiver is done again by its faces.
  Scene s;
  s.materials.push_back(Material{});
  Light l;
  l.shape = LightShape::rect;
  l.center = Vec3(0.5f, 2.0f, 0.5f);
  l.edge_u = Vec3(1.0f, 0.0f, 0.0f);
  l.edge_v = Vec3(0.0f, 0.0f, 1.0f);
  s.lights.push_back(l);
  s.meshes.push_back(grid_box(Vec3(0.0f, 1.0f, 0.35f), Vec3(1.0f, 1.5f, 0.65f), 10));
  const ExactScene edges(s, 8, true, true), faces(s, 8, true, false);
  ASSERT_EQ(edges.edge_trees().size(), 1u);
  const ExactLight light(s, s.lights[0]);
  const ExactPointResult in_plane = exact_visibility(edges, light, Vec3(0.0f, 0.0f, 0.5f));
  EXPECT_EQ(in_plane.edge_tree_fallbacks, 1u);
  EXPECT_NEAR(in_plane.visible, exact_visibility(faces, light, Vec3(0.0f, 0.0f, 0.5f)).visible,
              kGrid);
  EXPECT_GT(in_plane.visible, 0.0);
  EXPECT_LT(in_plane.visible, 1.0);
  // Beside that plane the edge tree answers.
  const ExactPointResult beside = exact_visibility(edges, light, Vec3(0.3f, 0.0f, 0.5f));
  EXPECT_EQ(beside.edge_tree_fallbacks, 0u);
  EXPECT_EQ(beside.edge_tree_solids, 1u);
  EXPECT_NEAR(beside.visible, exact_visibility(faces, light, Vec3(0.3f, 0.0f, 0.5f)).visible,
              kGrid);
}

TEST(ExactEdgeTrees, RoundLightsUseTheFaces) {
  // The edge trees serve the area sweep (uniform rectangles); a disk light keeps Clipper's path.
  Scene s = test::sphere_over_ground(fine({}));
  s.lights[0].shape = LightShape::disk;
  const ExactScene edges(s, 8, true, true);
  const ExactLight light(s, s.lights[0]);
  uint64_t by_edges = 0;
  for (const Vec3& p : receivers()) by_edges += exact_visibility(edges, light, p).edge_tree_solids;
  EXPECT_EQ(by_edges, 0u);
}

TEST(ExactEdgeTrees, MethodOptionAgreesOnTheDragonFrame) {
  // Through the method on a built-in model scene (the procedural stand-in when the models are
  // not fetched): images equal to float precision, the path taken.
  const test::TestFrame t = test::make_test_frame("dragon", 40, 40, test::grid_samples(2));
  const MethodResult on = t.run("exact"), off = t.run("exact", {{"edge_trees", "false"}});
  const Visibility &e = on.per_light[0], &f = off.per_light[0];
  float max_diff = 0.0f;
  for (size_t i = 0; i < e.lit.pixels().size(); ++i)
    max_diff = std::max(max_diff, std::abs(e.lit.pixels()[i] - f.lit.pixels()[i]));
  EXPECT_LE(max_diff, 6e-8f);
  EXPECT_GT(e.counters.at("edge_tree_silhouettes"), 100.0);
  EXPECT_EQ(f.counters.at("edge_tree_silhouettes"), 0.0);
}

TEST(ExactEdgeTrees, GardenFoliageWithManyEdges) {
  // Alpha-cut leaves give hundreds of piece edges per receiver: the divided sweep groups them
  // per cut triangle. Against raytrace with 16 × 16 samples, whose own error is of that order.
  const test::TestFrame t = test::make_test_frame("garden", 6, 6, test::grid_samples(16));
  const MethodResult exact = t.run("exact"), ray = t.run("raytrace");
  const Visibility &e = exact.per_light[0], &r = ray.per_light[0];
  double sum = 0.0;
  int n = 0;
  for (size_t i = 0; i < e.lit.pixels().size(); ++i) {
    if (t.frame->receivers(0).pixels()[i] != kActive) continue;
    const double d = std::abs(e.lit.pixels()[i] - r.lit.pixels()[i]);
    EXPECT_LE(d, 0.06) << i;
    sum += d;
    ++n;
  }
  ASSERT_GT(n, 20);
  EXPECT_LE(sum / n, 0.01);
  EXPECT_GT(e.counters.at("silhouette_edges") / n, 384.0);  // the divided sweep ran
}

}  // namespace
}  // namespace penumbra
