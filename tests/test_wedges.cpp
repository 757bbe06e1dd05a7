// `wedges` (penumbra wedges, Assarsson 2003 III–IV, Forest 2008 §3.1): the analytic coverage
// against closed forms, exactness for a single planar convex occluder against `exact` (Assarsson
// 2003 III §5.3), the point-light limit (= shadow_volume), the camera inside the shadow volume and
// inside a wedge, and measured (not bounded) errors on spheres and bunny.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>

#include "penumbra/render/receivers.hpp"
#include "penumbra/scene/model_paths.hpp"
#include "penumbra/scene/shapes.hpp"
#include "penumbra/shadows/wedges/coverage.hpp"
#include "penumbra/shadows/wedges/geometry.hpp"
#include "penumbra/shadows/wedges/pass.hpp"
#include "support/frame_helpers.hpp"

namespace penumbra {
namespace {

using test::make_test_frame;
using test::TestFrame;

/// c of the quad texture bound max |ΔV| ≤ c/(n − 1) (docs/methods/wedges.md).
constexpr double kQuadTextureC = 4.0;
/// The same for the RGB table of a textured light, per channel, times the channel's maximum
/// normalised emission density ρ_max (docs/methods/wedges.md "Textured lights").
constexpr double kQuadTextureRgbC = 7.5;

/// Where a wedge method is exact (one planar convex occluder, [Assarsson 2003 III §5.3]), its error
/// against `exact` is float rounding of V: measured ≤ 1.34e-7 (disk light on `quad`), 3e-8 on most.
constexpr double kExactTol = 4e-7;

/// A measured mean error (docs/methods/wedges.md) held to within 5 % of itself: a change of the
/// method's approximation (another overlap rule, no blending heuristic, another split) moves it
/// far more.
void expect_measured(double got, double measured, const char* what) {
  EXPECT_NEAR(got, measured, 0.05 * measured) << what;
}

LightSampleSpec one_sample() {
  LightSampleSpec s;
  s.pattern = SamplePattern::grid;
  s.k = 1;
  return s;
}

struct Diff {
  double max_abs = 0.0, mean_abs_shadowed = 0.0;
  int active = 0, shadowed = 0, penumbra = 0;
};

/// |method − reference| over the active pixels; "shadowed" = reference below 1 − 1e-4.
Diff compare(const TestFrame& t, const std::string& method,
             const std::map<std::string, std::string>& options = {},
             const std::string& reference = "exact") {
  const MethodResult a = t.run(method, options);
  const MethodResult r = t.run(reference);
  const Image<float>& va = a.per_light[0].lit;
  const Image<float>& vr = r.per_light[0].lit;
  Diff d;
  double sum = 0.0;
  for (size_t i = 0; i < va.size(); ++i) {
    if (t.frame->receivers(0)[i] != kActive) continue;
    ++d.active;
    const double e = std::abs(static_cast<double>(va[i]) - vr[i]);
    d.max_abs = std::max(d.max_abs, e);
    if (vr[i] < 1.0f - 1e-4f) {
      ++d.shadowed;
      sum += e;
      d.penumbra += vr[i] > 1e-4f;
    }
  }
  d.mean_abs_shadowed = d.shadowed ? sum / d.shadowed : 0.0;
  return d;
}

/// Both wedge constructions (wedges/geometry.hpp): every exactness test runs with each.
constexpr const char* kConstructions[] = {"paper", "hull"};

void print(const char* what, const Diff& d) {
  std::printf("    %-34s max %.2e  mean(shadowed) %.5f  active %d shadowed %d penumbra %d\n", what,
              d.max_abs, d.mean_abs_shadowed, d.active, d.shadowed, d.penumbra);
}

/// `method` (with `options`) against `exact` under every wedge construction: max |Δ| ≤ kExactTol,
/// with more than `min_penumbra` penumbra pixels (so that a real penumbra is being checked).
void expect_exact_per_construction(const TestFrame& t, const std::string& method, int min_penumbra,
                                   std::map<std::string, std::string> options = {}) {
  for (const char* c : kConstructions) {
    options["construction"] = c;
    const Diff d = compare(t, method, options);
    print((method + ", " + c).c_str(), d);
    EXPECT_LE(d.max_abs, kExactTol) << method << ", " << c;
    EXPECT_GT(d.penumbra, min_penumbra) << method << ", " << c;
  }
}

/// `quad` under a disk light inscribed in its square light, facing down.
Scene disk_light_quad() {
  Scene s = make_builtin_scene("quad");
  Light& l = s.lights[0];
  l.shape = LightShape::disk;
  l.radius = 0.5f * glm::length(l.edge_u);
  l.normal = Vec3(0, -1, 0);
  return s;
}

TEST(WedgeCoverage, SquareHalfPlaneAboveAChord) {
  // Horizontal segment at v = 0.75 spanning the square, left to right: (c, a, b) is clockwise
  // in uv, and the area beyond it (v > 0.75) is 0.25.
  EXPECT_NEAR(square_sector_minus_triangle({0.0, 0.75}, {1.0, 0.75}), -0.25, 1e-12);
  EXPECT_NEAR(square_sector_minus_triangle({1.0, 0.75}, {0.0, 0.75}), 0.25, 1e-12);
  // A diagonal through the square's corners (1,0)–(0,1): beyond it the triangle of area 1/2 is
  // split... the sector from c spans 180°, the triangle (c, a, b) is degenerate: half the square.
  EXPECT_NEAR(std::abs(square_sector_minus_triangle({1.0, 0.0}, {0.0, 1.0})), 0.0, 1e-12);
  // A short segment inside: the region between it and the boundary within the sector.
  // a = (0.75, 0.5), b = (0.5, 0.75): sector = quarter square 0.25, triangle 1/32.
  EXPECT_NEAR(square_sector_minus_triangle({0.75, 0.5}, {0.5, 0.75}), 0.25 - 1.0 / 32.0, 1e-12);
}

TEST(WedgeCoverage, DiskSegmentIsTheCircularSegment) {
  DVec2 a(0.0, 0.75), b(1.0, 0.75);
  ASSERT_TRUE(clip_edge_to_light_disk(a, b));
  EXPECT_NEAR(a.x, 0.5 - std::sqrt(0.1875), 1e-12);
  const double r = 0.5, d = 0.25;
  const double segment = r * r * std::acos(d / r) - d * std::sqrt(r * r - d * d);
  EXPECT_NEAR(disk_sector_minus_triangle(a, b), -segment, 1e-12);
}

TEST(WedgeCoverage, ClipsHomogeneousSegments) {
  DVec2 a, b;
  // W = 0.5 at both ends: uv = (U, V) / W.
  ASSERT_TRUE(clip_edge_to_light_square({-0.5, 0.25, 0.5}, {1.0, 0.25, 0.5}, a, b));
  EXPECT_NEAR(a.x, 0.0, 1e-12);
  EXPECT_NEAR(b.x, 1.0, 1e-12);
  EXPECT_NEAR(a.y, 0.5, 1e-12);
  // Entirely beyond the light plane (W > 1) or behind the receiver (W < 0): nothing.
  EXPECT_FALSE(clip_edge_to_light_square({0.1, 0.1, 1.5}, {0.2, 0.2, 2.0}, a, b));
  EXPECT_FALSE(clip_edge_to_light_square({0.1, 0.1, -1.0}, {0.2, 0.2, -0.5}, a, b));
}

/// Paper III §5.3: one planar convex occluder — the silhouette is the same from every light point
/// and nothing overlaps, so the method is exact up to rounding.
TEST(Wedges, QuadMatchesExact) {
  const auto t = make_test_frame("quad", 64, 64, one_sample());
  expect_exact_per_construction(t, "wedges", 200);
}

Scene tilted_triangle_scene() {
  Scene s = make_builtin_scene("quad");
  Mesh tri;
  tri.name = "triangle";
  tri.positions = {Vec3(-0.5f, 0.7f, -0.3f), Vec3(0.6f, 1.1f, -0.1f), Vec3(-0.1f, 0.9f, 0.6f)};
  tri.triangles = {{{0, 1, 2}}};
  tri.material = s.meshes[1].material;
  s.meshes[1] = tri;
  return s;
}

TEST(Wedges, TiltedTriangleMatchesExact) {
  const auto t = make_test_frame(tilted_triangle_scene(), 64, 64, one_sample());
  expect_exact_per_construction(t, "wedges", 200);
}

TEST(Wedges, DiskLightOnQuadMatchesExact) {
  const auto t = make_test_frame(disk_light_quad(), 64, 64, one_sample());
  expect_exact_per_construction(t, "wedges", 200);
}

/// A sphere light: `exact` and `wedges` both use the silhouette disk seen from each receiver.
TEST(Wedges, SphereLightOnQuadMatchesExact) {
  Scene s = make_builtin_scene("quad");
  Light& l = s.lights[0];
  l.shape = LightShape::sphere;
  l.radius = 0.5f * glm::length(l.edge_u);
  const auto t = make_test_frame(std::move(s), 64, 64, one_sample());
  expect_exact_per_construction(t, "wedges", 100);
}

/// With no light extent there are no wedges: the hard count from the centre is the answer.
TEST(Wedges, PointLightEqualsShadowVolume) {
  for (const char* name : {"quad", "spheres"}) {
    Scene s = make_builtin_scene(name);
    s.lights[0].shape = LightShape::point;
    const auto t = make_test_frame(std::move(s), 64, 64, one_sample());
    const Diff d = compare(t, "wedges", {}, "shadow_volume");
    print(name, d);
    EXPECT_EQ(d.max_abs, 0.0) << name;
    EXPECT_GT(d.shadowed, 100) << name;
  }
}

/// The camera between the quad and the ground, looking across the umbra and the penumbra: every
/// test is per G-buffer point in world space, so nothing depends on where the camera is
/// [Assarsson 2003 III §5.3; Forest 2008 §3.1.3].
TEST(Wedges, CameraInsideTheShadowVolume) {
  Scene s = make_builtin_scene("quad");
  s.camera.position = Vec3(0.1f, 0.5f, 0.15f);
  s.camera.target = Vec3(0.9f, 0.0f, 1.1f);
  s.camera.vfov_deg = 70.0f;
  const auto t = make_test_frame(std::move(s), 64, 64, one_sample());
  expect_exact_per_construction(t, "wedges", 100);
}

TEST(Wedges, CameraInsideAWedge) {
  // Just below the quad's edge x = +occluder_side/2, in the penumbra region of that edge.
  Scene s = make_builtin_scene("quad");
  const Vec3 quad_corner = s.meshes[1].positions[0];
  float xmax = -1e9f;
  for (const Vec3& p : s.meshes[1].positions) xmax = std::max(xmax, p.x);
  s.camera.position = Vec3(xmax, quad_corner.y - 0.2f, 0.0f);
  s.camera.target = Vec3(xmax + 0.6f, 0.0f, 0.5f);
  s.camera.vfov_deg = 80.0f;
  // The camera really is inside the wedge of the quad's edge at x = xmax, for both constructions.
  // The quad is parallel to the light and centred under it, so both endpoints are at the same
  // distance from the light centre: the top edge is the edge, and both constructions give the same
  // wedge. The edge is parallel to a side of the light, so of each end pyramid's faces facing away
  // from the other end (Assarsson 2003 IV §4.1's "two leftmost and two rightmost triangles") two
  // coincide with the front and back planes: front, back and one face per end.
  const WedgeLight light = wedge_pass::wedge_light(s.lights[0]);
  std::vector<DVec3> edge;
  for (const Vec3& p : s.meshes[1].positions)
    if (p.x == xmax) edge.push_back(DVec3(p));
  ASSERT_EQ(edge.size(), 2u);
  for (WedgeConstruction c : {WedgeConstruction::paper, WedgeConstruction::hull}) {
    const Wedge w = build_wedge(edge[0], edge[1], 1.0, light, c, 1.0);
    EXPECT_EQ(w.plane_count, 4);
    EXPECT_FALSE(w.degenerate);
    EXPECT_TRUE(w.contains(DVec3(s.camera.position)));
  }
  const auto t = make_test_frame(std::move(s), 64, 64, one_sample());
  expect_exact_per_construction(t, "wedges", 100);
}

/// A light of each shape at (0, 2, 0), emitting downward (rect, disk) or all around (sphere).
Light test_light(LightShape shape) {
  Light l;
  l.shape = shape;
  l.center = Vec3(0.0f, 2.0f, 0.0f);
  l.edge_u = Vec3(0.6f, 0.0f, 0.0f);
  l.edge_v = Vec3(0.0f, 0.0f, 0.4f);
  l.normal = Vec3(0.0f, -1.0f, 0.0f);
  l.radius = 0.3f;
  return l;
}

/// A uniformly random emitting point of the light (for the sphere: any point of the ball, a
/// superset of every receiver's silhouette disk).
DVec3 random_light_point(const Light& l, std::mt19937& rng) {
  std::uniform_real_distribution<double> u01(0.0, 1.0), u11(-1.0, 1.0);
  if (l.shape == LightShape::rect)
    return DVec3(l.center) + (u01(rng) - 0.5) * DVec3(l.edge_u) +
           (u01(rng) - 0.5) * DVec3(l.edge_v);
  for (;;) {
    const DVec3 p(u11(rng), l.shape == LightShape::disk ? 0.0 : u11(rng), u11(rng));
    if (glm::dot(p, p) <= 1.0) return DVec3(l.center) + static_cast<double>(l.radius) * p;
  }
}

/// Does the segment meet the (one-sided, planar) light? Then points behind its plane are exempt
/// (wedges/geometry.hpp: the clip to the emitting side).
bool meets_light(const Light& l, const DVec3& a, const DVec3& b) {
  const double ha = a.y - l.center.y, hb = b.y - l.center.y;
  if ((ha > 0.0) == (hb > 0.0) && ha != 0.0 && hb != 0.0) return false;
  const DVec3 q = a + (ha / (ha - hb)) * (b - a) - DVec3(l.center);
  if (l.shape == LightShape::disk) return std::hypot(q.x, q.z) <= l.radius * (1.0 + 1e-6);
  return std::abs(q.x) <= 0.3 + 1e-6 && std::abs(q.z) <= 0.2 + 1e-6;
}

/// The lemma of wedges/geometry.hpp, sampled: every point x + t(X − x) (x on the light, X on the
/// edge, t > 1) lies in the wedge, for each light shape and both constructions, for random edges
/// (below, beside and above the light, crossing its plane, some through the light itself).
TEST(WedgeGeometry, WedgesContainTheEdgeRegion) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u01(0.0, 1.0), pos(-1.5, 1.5);
  for (LightShape shape : {LightShape::rect, LightShape::disk, LightShape::sphere}) {
    const Light light = test_light(shape);
    const WedgeLight wl = wedge_pass::wedge_light(light);
    int checked = 0, degenerate = 0, through = 0;
    for (int e = 0; e < 300; ++e) {
      DVec3 a(pos(rng), 2.0 + pos(rng) * 1.4, pos(rng)),
          b = a + 0.6 * DVec3(pos(rng), pos(rng), pos(rng));
      if (e % 25 == 0) {  // through the light: from above to below, across its middle
        a = DVec3(light.center) + DVec3(0.1 * pos(rng), 0.3, 0.1 * pos(rng));
        b = DVec3(light.center) + DVec3(0.1 * pos(rng), -0.5, 0.1 * pos(rng));
      }
      const bool exempt_behind = shape != LightShape::sphere && meets_light(light, a, b);
      through += exempt_behind;
      for (WedgeConstruction c : {WedgeConstruction::paper, WedgeConstruction::hull}) {
        const Wedge w = build_wedge(a, b, 1.0, wl, c, 10.0);
        degenerate += w.degenerate;
        for (int k = 0; k < w.plane_count; ++k) {
          ASSERT_TRUE(std::isfinite(w.planes[k].d));
          ASSERT_NEAR(glm::length(w.planes[k].n), 1.0, 1e-9);
        }
        for (int s = 0; s < 400; ++s) {
          const DVec3 x = random_light_point(light, rng), X = a + u01(rng) * (b - a);
          const double t = 1.0 + 19.0 * u01(rng);
          const DVec3 y = x + t * (X - x);
          if (exempt_behind && y.y >= light.center.y) continue;  // behind (emits toward −y)
          ++checked;
          ASSERT_TRUE(w.contains(y)) << "shape " << static_cast<int>(shape) << " construction "
                                     << static_cast<int>(c) << " edge " << e << " t " << t;
        }
      }
    }
    std::printf(
        "    shape %d: %d points checked, %d degenerate wedges, %d edges through the light\n",
        static_cast<int>(shape), checked, degenerate, through);
    EXPECT_GT(checked, 200000);
  }
}

/// An edge touching a one-sided light from its emitting side: the wedge is the emitting
/// half-space (Assarsson 2003 IV §4.1), finite, and holds the region below.
TEST(WedgeGeometry, EdgeTouchingTheLightGivesAHalfSpace) {
  for (LightShape shape : {LightShape::rect, LightShape::disk}) {
    const Light light = test_light(shape);
    const WedgeLight wl = wedge_pass::wedge_light(light);
    const DVec3 a = DVec3(light.center) + DVec3(0.05, 0.2, 0.0);
    const DVec3 b = DVec3(light.center) + DVec3(-0.05, -0.4, 0.02);
    for (WedgeConstruction c : {WedgeConstruction::paper, WedgeConstruction::hull}) {
      const Wedge w = build_wedge(a, b, 1.0, wl, c, 10.0);
      EXPECT_TRUE(w.degenerate);
      EXPECT_GE(w.plane_count, 1);
      EXPECT_TRUE(std::isfinite(w.top0.y) && std::isfinite(w.top1.y));
      EXPECT_GE(std::min(w.top0.y, w.top1.y), light.center.y - 0.4 - 1e-12);
      EXPECT_LE(std::max(w.top0.y, w.top1.y),
                light.center.y + 1e-12);  // clipped to the emitting side
      EXPECT_TRUE(w.contains(DVec3(0.0, 0.0, 0.0)));
      EXPECT_TRUE(w.contains(DVec3(3.0, 1.9, -2.0)));
      EXPECT_FALSE(w.contains(DVec3(0.0, 2.1, 0.0)));  // behind the light: outside
    }
  }
}

/// Points of a grid below the light inside the wedges of random edges: Assarsson 2003 IV §4.1's
/// wedge for a rectangle (tangent to its corners, pyramid faces) is tighter than Assarsson 2003
/// III's wedge from the rectangle's bounding sphere, and `hull` is tighter than `paper`.
TEST(WedgeGeometry, RectangleWedgesAreTighterThanBoundingSphereWedges) {
  const Light light = test_light(LightShape::rect);
  const WedgeLight rect = wedge_pass::wedge_light(light);
  WedgeLight sphere = rect;
  sphere.round = true;
  sphere.radius = 0.5 * std::hypot(0.6, 0.4);
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> pos(-1.0, 1.0);
  uint64_t in_rect = 0, in_sphere = 0, in_hull = 0;
  for (int e = 0; e < 60; ++e) {
    const DVec3 a(pos(rng), 1.0 + 0.4 * pos(rng), pos(rng));
    const DVec3 b = a + 0.5 * DVec3(pos(rng), 0.5 * pos(rng), pos(rng));
    const Wedge wr = build_wedge(a, b, 1.0, rect, WedgeConstruction::paper, 10.0);
    const Wedge ws = build_wedge(a, b, 1.0, sphere, WedgeConstruction::paper, 10.0);
    const Wedge wh = build_wedge(a, b, 1.0, rect, WedgeConstruction::hull, 10.0);
    for (int i = 0; i < 40; ++i)
      for (int j = 0; j < 40; ++j)
        for (int k = 0; k < 8; ++k) {
          const DVec3 y(-4.0 + 0.2 * i, 0.1 * k, -4.0 + 0.2 * j);
          in_rect += wr.contains(y);
          in_sphere += ws.contains(y);
          in_hull += wh.contains(y);
        }
  }
  std::printf(
      "    grid points inside: rect (Assarsson 2003 IV 4.1) %llu, bounding sphere %llu, hull "
      "%llu\n",
      static_cast<unsigned long long>(in_rect), static_cast<unsigned long long>(in_sphere),
      static_cast<unsigned long long>(in_hull));
  EXPECT_LT(in_rect, in_sphere);
  EXPECT_LE(in_hull, in_rect);
  EXPECT_GT(in_hull, 1000u);
}

/// Per frame: `hull` (screen bound from the real edge) tests no more pixels than `paper` (top
/// edge), both exact.
TEST(Wedges, HullTestsNoMorePixelsThanPaper) {
  for (const char* name : {"quad", "spheres"}) {
    const auto t = make_test_frame(name, 64, 64, one_sample());
    const MethodResult p = t.run("wedges", {{"construction", "paper"}});
    const MethodResult h = t.run("wedges", {{"construction", "hull"}});
    const auto& cp = p.per_light[0].counters;
    const auto& ch = h.per_light[0].counters;
    std::printf("    %s: pixel tests paper %.0f hull %.0f, inside paper %.0f hull %.0f\n", name,
                cp.at("pixel_tests"), ch.at("pixel_tests"), cp.at("pixels_inside_wedges"),
                ch.at("pixels_inside_wedges"));
    EXPECT_LE(ch.at("pixel_tests"), cp.at("pixel_tests")) << name;
    EXPECT_LE(ch.at("pixels_inside_wedges"), cp.at("pixels_inside_wedges")) << name;
    EXPECT_EQ(ch.at("pixels_covered"), cp.at("pixels_covered")) << name;
    EXPECT_GT(ch.at("pixels_covered"), 100.0) << name;
  }
}

/// One planar convex occluder: one group, whose SV-buffer is the exact per-part occlusion, so
/// blending (Forest 2008 §3.2) and the overlap approximation (Assarsson 2003 IV §5.1) change
/// nothing.
TEST(WedgeBlend, QuadMatchesExactAndWedges) {
  const auto t = make_test_frame("quad", 64, 64, one_sample());
  for (const char* c : kConstructions) {
    const Diff d = compare(t, "wedge_blend", {{"construction", c}});
    const Diff dw = compare(t, "wedge_blend", {{"construction", c}}, "wedges");
    const Diff dov = compare(t, "wedges", {{"overlap", "true"}, {"construction", c}});
    print("quad, wedge_blend", d);
    print("quad, wedge_blend vs wedges", dw);
    print("quad, overlap", dov);
    EXPECT_LE(d.max_abs, kExactTol) << c;
    EXPECT_EQ(dw.max_abs, 0.0) << c;
    EXPECT_LE(dov.max_abs, kExactTol) << c;
    EXPECT_GT(d.penumbra, 200) << c;
  }
}

TEST(WedgeBlend, TiltedTriangleMatchesExact) {
  const auto t = make_test_frame(tilted_triangle_scene(), 48, 48, one_sample());
  expect_exact_per_construction(t, "wedge_blend", 100);
}

TEST(WedgeBlend, DiskLightOnQuadMatchesExact) {
  const auto t = make_test_frame(disk_light_quad(), 48, 48, one_sample());
  expect_exact_per_construction(t, "wedge_blend", 100);
}

/// Point light: no wedges; blending the groups' hard counts gives the hard shadow.
TEST(WedgeBlend, PointLightEqualsShadowVolume) {
  Scene s = make_builtin_scene("spheres");
  s.lights[0].shape = LightShape::point;
  const auto t = make_test_frame(std::move(s), 48, 48, one_sample());
  const Diff d = compare(t, "wedge_blend", {}, "shadow_volume");
  const Diff dov = compare(t, "wedges", {{"overlap", "true"}}, "shadow_volume");
  print("spheres, point light, wedge_blend", d);
  print("spheres, point light, overlap", dov);
  EXPECT_EQ(d.max_abs, 0.0);
  EXPECT_EQ(dov.max_abs, 0.0);
  EXPECT_GT(d.shadowed, 50);
}

/// Light splitting changes nothing where the method is already exact.
TEST(Wedges, SplitLightStaysExactOnQuad) {
  const auto t = make_test_frame("quad", 48, 48, one_sample());
  expect_exact_per_construction(t, "wedges", 100, {{"split", "3"}});
}

/// Measured (docs/methods/wedges.md): overlapping spheres, where the summed coverage over-darkens,
/// and the papers' remedies: light splitting (Assarsson 2003 IV §5.2, figs. 8–9), the overlap
/// approximation (Assarsson 2003 IV §5.1, eq. 1) and penumbra-wedge blending (Forest 2008 §3.2,
/// fig. 3.5). The papers claim splitting and blending each reduce the error of plain wedges there.
TEST(Wedges, MeasuredErrorOnSpheres) {
  const auto t = make_test_frame("spheres", 96, 96, one_sample());
  const Diff d1 = compare(t, "wedges");
  const Diff dov = compare(t, "wedges", {{"overlap", "true"}});
  const Diff d2 = compare(t, "wedges", {{"split", "2"}});
  const Diff d4 = compare(t, "wedges", {{"split", "4"}});
  const Diff db = compare(t, "wedge_blend");
  print("spheres", d1);
  print("spheres, overlap", dov);
  print("spheres, split 2", d2);
  print("spheres, split 4", d4);
  print("spheres, wedge_blend", db);
  EXPECT_GT(d1.shadowed, 500);
  EXPECT_LT(d2.mean_abs_shadowed, d1.mean_abs_shadowed);
  EXPECT_LT(d4.mean_abs_shadowed, d2.mean_abs_shadowed);
  EXPECT_LT(db.mean_abs_shadowed, d1.mean_abs_shadowed);
  EXPECT_LT(dov.mean_abs_shadowed, d1.mean_abs_shadowed);
  // The measured figures (96², one sample): a plain sum in place of eq. 1 gives plain wedges'
  // 0.0983 for `overlap`, and blending without eq. 3.1's overlapped-area estimate 0.045.
  expect_measured(d1.mean_abs_shadowed, 0.0992, "wedges");
  expect_measured(dov.mean_abs_shadowed, 0.0532, "overlap");
  expect_measured(d2.mean_abs_shadowed, 0.0449, "split 2");
  expect_measured(d4.mean_abs_shadowed, 0.0142, "split 4");
  expect_measured(db.mean_abs_shadowed, 0.0222, "wedge_blend");
}

TEST(Wedges, MeasuredErrorOnBunny) {
  if (!find_model("bunny00.off")) GTEST_SKIP() << "bunny not fetched: run scripts/fetch-models.sh";
  const auto t = make_test_frame("bunny", 96, 96, one_sample());
  const Diff d1 = compare(t, "wedges");
  const Diff d2 = compare(t, "wedges", {{"split", "2"}});
  const Diff dov = compare(t, "wedges", {{"overlap", "true"}});
  const Diff db = compare(t, "wedge_blend");
  print("bunny", d1);
  print("bunny, split 2", d2);
  print("bunny, overlap", dov);
  print("bunny, wedge_blend", db);
  EXPECT_GT(d1.shadowed, 100);
  expect_measured(d1.mean_abs_shadowed, 0.0474, "wedges");
  expect_measured(d2.mean_abs_shadowed, 0.0212, "split 2");
  expect_measured(dov.mean_abs_shadowed, 0.0444, "overlap");
  expect_measured(db.mean_abs_shadowed, 0.0387, "wedge_blend");
}

/// Paper III §3.3's 4D coverage texture: the derived per-pair bound (coverage_texture_bound,
/// docs/methods/wedges.md "Coverage texture") holds for random endpoint pairs, the table is exact
/// on its grid, and the error on the light's border (where most clipped endpoints lie) shrinks
/// like 1/n.
TEST(CoverageTexture, DerivedBoundHoldsAndConverges) {
  using L = CoverageTexture::Lookup;
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const auto on_border = [&]() {
    const double t = u(rng);
    switch (static_cast<int>(u(rng) * 4.0) & 3) {
      case 0:
        return DVec2(t, 0.0);
      case 1:
        return DVec2(1.0, t);
      case 2:
        return DVec2(t, 1.0);
      default:
        return DVec2(0.0, t);
    }
  };
  double prev_border[2] = {1.0, 1.0};
  for (int n : {16, 32, 64}) {
    const CoverageTexture tex(n);
    const double h = 1.0 / (n - 1);
    EXPECT_NEAR(tex.unsigned_coverage({3 * h, 0.0}, {1.0, 5 * h}, L::bilinear),
                std::abs(square_sector_minus_triangle({3 * h, 0.0}, {1.0, 5 * h})), 1e-6);
    for (L lookup : {L::bilinear, L::quadrilinear}) {
      double worst_ratio = 0.0, border_max = 0.0;
      for (int k = 0; k < 20000; ++k) {
        const bool border = k % 2 == 0;
        const DVec2 a = border ? on_border() : DVec2(u(rng), u(rng));
        const DVec2 b = border ? on_border() : DVec2(u(rng), u(rng));
        const double exact = square_sector_minus_triangle(a, b);
        const double err = std::abs(tex.sector_minus_triangle(a, b, lookup) - exact);
        const double bound = coverage_texture_bound(a, b, n, lookup) + 1e-6;
        EXPECT_LE(err, bound) << "n " << n << " a " << a.x << "," << a.y << " b " << b.x << ","
                              << b.y;
        worst_ratio = std::max(worst_ratio, err / bound);
        if (border) border_max = std::max(border_max, err);
      }
      const int li = lookup == L::bilinear ? 0 : 1;
      std::printf("    n %2d %-12s border max err %.2e (x(n-1) = %.3f), worst err/bound %.2f\n", n,
                  li ? "quadrilinear" : "bilinear", border_max, border_max * (n - 1), worst_ratio);
      // Both endpoints on the border: d = 1/2, the bound is about 2.1·h·L(1/2) ≈ 2·h.
      EXPECT_LE(border_max, 2.5 * h);
      EXPECT_LT(border_max, prev_border[li]);
      prev_border[li] = border_max;
    }
  }
}

/// The texture path of `wedges` on `quad` (exact analytically): its error against `exact` is the
/// discretisation error alone, within c/(n − 1) (c derived in docs/methods/wedges.md), and
/// shrinks as n grows 8 → 16 → 32.
TEST(Wedges, CoverageTextureOnQuadConverges) {
  const auto t = make_test_frame("quad", 64, 64, one_sample());
  for (const char* lookup : {"bilinear", "quadrilinear"}) {
    double prev = 1.0;
    for (int n : {8, 16, 32}) {
      const Diff d =
          compare(t, "wedges",
                  {{"coverage", "texture"}, {"texture_n", std::to_string(n)}, {"lookup", lookup}});
      char what[64];
      std::snprintf(what, sizeof what, "quad, texture n %d %s", n, lookup);
      print(what, d);
      std::printf("      max x (n-1) = %.3f\n", d.max_abs * (n - 1));
      EXPECT_LE(d.max_abs, kQuadTextureC / (n - 1)) << lookup << " n " << n;
      EXPECT_LT(d.max_abs, prev) << lookup << " n " << n;
      prev = d.max_abs;
    }
  }
  // The analytic path is untouched by the option's existence.
  EXPECT_LE(compare(t, "wedges", {{"coverage", "analytic"}}).max_abs, kExactTol);
}

using test::with_textured_light;

Scene textured_quad() {
  return with_textured_light(make_builtin_scene("quad"));
}

/// max |Δ| per channel of lit_rgb and of lit, method against exact; mean |Δ| per channel over the
/// pixels exact shadows.
struct RgbDiff {
  DVec3 max_rgb{0.0}, mean_rgb_shadowed{0.0};
  double max_lit = 0.0, max_lum = 0.0;
  int penumbra = 0, shadowed = 0;
};
RgbDiff compare_rgb(const TestFrame& t, const std::map<std::string, std::string>& options,
                    const std::string& method = "wedges") {
  const MethodResult a = t.run(method, options);
  const MethodResult r = t.run("exact");
  const Visibility& va = a.per_light[0];
  const Visibility& vr = r.per_light[0];
  EXPECT_TRUE(va.lit_rgb.has_value());
  EXPECT_TRUE(vr.lit_rgb.has_value());
  RgbDiff d;
  if (!va.lit_rgb || !vr.lit_rgb) return d;
  const Scene& s = *t.scene;
  const Texture& tex = s.textures[s.lights[0].emission_texture];
  const LightEmission em(tex, s.lights[0].radiance);
  for (size_t i = 0; i < va.lit.size(); ++i) {
    if (t.frame->receivers(0)[i] != kActive) continue;
    const Vec3 ca = (*va.lit_rgb)[i], cr = (*vr.lit_rgb)[i];
    for (int c = 0; c < 3; ++c)
      d.max_rgb[c] = std::max(d.max_rgb[c], std::abs(static_cast<double>(ca[c]) - cr[c]));
    d.max_lit = std::max(d.max_lit, std::abs(static_cast<double>(va.lit[i]) - vr.lit[i]));
    // lit is the Rec. 709 luminance ratio of lit_rgb weighted by the light's emission.
    double seen = 0.0, all = 0.0;
    const double lum[3] = {0.2126, 0.7152, 0.0722};
    for (int c = 0; c < 3; ++c) {
      seen += lum[c] * em.total[c] * ca[c];
      all += lum[c] * em.total[c];
    }
    d.max_lum = std::max(d.max_lum, std::abs(seen / all - va.lit[i]));
    d.penumbra += vr.lit[i] > 1e-4f && vr.lit[i] < 1.0f - 1e-4f;
    if (vr.lit[i] < 1.0f - 1e-4f) {
      ++d.shadowed;
      for (int c = 0; c < 3; ++c)
        d.mean_rgb_shadowed[c] += std::abs(static_cast<double>(ca[c]) - cr[c]);
    }
  }
  if (d.shadowed) d.mean_rgb_shadowed /= static_cast<double>(d.shadowed);
  return d;
}

/// The emission-weighted coverage: a uniform texture gives the analytic area; random pairs of the
/// RGB table stay within the derived per-pair bound (docs/methods/wedges.md "Textured lights").
TEST(CoverageTexture, RgbTableWithinDerivedBound) {
  Texture flat;
  flat.width = 3;
  flat.height = 2;
  flat.channels = 1;
  flat.texels.assign(6, 0.7f);
  const LightEmission uniform(flat, Vec3(1.0f, 2.0f, 0.5f));
  const Scene s = textured_quad();
  const LightEmission em(s.textures[0], s.lights[0].radiance);
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (int k = 0; k < 2000; ++k) {
    const DVec2 a(u(rng), u(rng)), b(u(rng), u(rng));
    const DVec3 w = weighted_sector_minus_triangle(uniform, a, b);
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(w[c], square_sector_minus_triangle(a, b), 1e-12);
  }
  using L = CoverageTexture::Lookup;
  for (int n : {16, 32}) {
    const CoverageTextureRGB tex(n, em);
    for (L lookup : {L::bilinear, L::quadrilinear}) {
      double worst_ratio = 0.0;
      for (int k = 0; k < 10000; ++k) {
        DVec2 a(u(rng), u(rng)), b(u(rng), u(rng));
        if (k % 2) {  // half on the border, like most clipped endpoints
          a[k % 4 == 1 ? 0 : 1] = std::round(a[k % 4 == 1 ? 0 : 1]);
          b[k % 4 == 1 ? 1 : 0] = std::round(b[k % 4 == 1 ? 1 : 0]);
        }
        const DVec3 exact = weighted_sector_minus_triangle(em, a, b);
        const DVec3 got = tex.sector_minus_triangle(a, b, lookup);
        for (int c = 0; c < 3; ++c) {
          const double bound =
              coverage_texture_rgb_bound(a, b, n, lookup, em.max_density[c]) + 1e-6;
          const double err = std::abs(got[c] - exact[c]);
          EXPECT_LE(err, bound) << "n " << n << " pair " << k << " channel " << c;
          if (std::isfinite(bound)) worst_ratio = std::max(worst_ratio, err / bound);
        }
      }
      std::printf("    rgb table n %d %s: worst error/bound %.3f\n", n,
                  lookup == L::bilinear ? "bilinear" : "quadrilinear", worst_ratio);
    }
  }
}

/// `quad` under a 2×2 RGB-textured light: the exact emission-weighted coverage (coverage =
/// analytic) reproduces exact's lit_rgb (the method is exact for one planar convex occluder), and
/// the RGB table (coverage = texture) stays within ρ_max,c · kQuadTextureRgbC / (n − 1) per
/// channel, shrinking with n; lit is the luminance ratio of lit_rgb.
TEST(Wedges, TexturedLightRgbOnQuad) {
  const auto t = make_test_frame(textured_quad(), 64, 64, one_sample());
  const Scene& s = *t.scene;
  const LightEmission em(s.textures[0], s.lights[0].radiance);
  const RgbDiff d0 = compare_rgb(t, {});
  std::printf("    textured quad, analytic: max rgb %.2e %.2e %.2e  lit %.2e  lum %.2e  pen %d\n",
              d0.max_rgb[0], d0.max_rgb[1], d0.max_rgb[2], d0.max_lit, d0.max_lum, d0.penumbra);
  for (int c = 0; c < 3; ++c) EXPECT_LE(d0.max_rgb[c], kExactTol) << c;
  EXPECT_LE(d0.max_lit, kExactTol);
  EXPECT_LE(d0.max_lum, kExactTol);
  EXPECT_GT(d0.penumbra, 200);
  // One group: the per-channel overlap approximation changes nothing.
  const RgbDiff dov = compare_rgb(t, {{"overlap", "true"}});
  for (int c = 0; c < 3; ++c) EXPECT_LE(dov.max_rgb[c], kExactTol) << c;
  // Light splitting [Assarsson 2003 IV §5.2] with the texture cut between the sub-lights: still
  // exact for one planar convex occluder, also when the cuts fall inside texels (2 texels, 3
  // sub-lights).
  for (const char* split : {"2", "3"}) {
    const RgbDiff ds = compare_rgb(t, {{"split", split}});
    std::printf("    textured quad, split %s: max rgb %.2e %.2e %.2e  lit %.2e  lum %.2e\n", split,
                ds.max_rgb[0], ds.max_rgb[1], ds.max_rgb[2], ds.max_lit, ds.max_lum);
    for (int c = 0; c < 3; ++c) EXPECT_LE(ds.max_rgb[c], kExactTol) << split << " channel " << c;
    EXPECT_LE(ds.max_lum, kExactTol) << split;
  }
  for (const char* lookup : {"bilinear", "quadrilinear"}) {
    DVec3 prev(1.0);
    for (int n : {8, 16, 32}) {
      const RgbDiff d = compare_rgb(
          t, {{"coverage", "texture"}, {"texture_n", std::to_string(n)}, {"lookup", lookup}});
      std::printf(
          "    textured quad, texture n %d %s: max rgb %.2e %.2e %.2e (x(n-1)/rho %.3f %.3f "
          "%.3f)  lit %.2e  lum %.2e\n",
          n, lookup, d.max_rgb[0], d.max_rgb[1], d.max_rgb[2],
          d.max_rgb[0] * (n - 1) / em.max_density[0], d.max_rgb[1] * (n - 1) / em.max_density[1],
          d.max_rgb[2] * (n - 1) / em.max_density[2], d.max_lit, d.max_lum);
      double lit_bound = 0.0;
      for (int c = 0; c < 3; ++c) {
        const double bound = em.max_density[c] * kQuadTextureRgbC / (n - 1);
        EXPECT_LE(d.max_rgb[c], bound) << lookup << " n " << n << " channel " << c;
        EXPECT_LT(d.max_rgb[c], prev[c]) << lookup << " n " << n << " channel " << c;
        lit_bound = std::max(lit_bound, bound);
      }
      EXPECT_LE(d.max_lit, lit_bound) << lookup << " n " << n;
      EXPECT_LE(d.max_lum, kExactTol);
      prev = d.max_rgb;
    }
  }
}

/// `wedge_blend` under a textured light: eq. 3.1's areas measured as emitted power per channel
/// (docs/methods/wedges.md). Exact on `quad` (one group: the SV-buffer is the exact per-part
/// occlusion), and on `spheres` it lowers every channel's error of plain `wedges`, as it does for a
/// uniform light (Forest fig. 3.5).
TEST(WedgeBlend, TexturedLightRgb) {
  const auto q = make_test_frame(textured_quad(), 64, 64, one_sample());
  const RgbDiff dq = compare_rgb(q, {}, "wedge_blend");
  std::printf("    textured quad, wedge_blend: max rgb %.2e %.2e %.2e  lit %.2e  lum %.2e\n",
              dq.max_rgb[0], dq.max_rgb[1], dq.max_rgb[2], dq.max_lit, dq.max_lum);
  for (int c = 0; c < 3; ++c) EXPECT_LE(dq.max_rgb[c], kExactTol) << c;
  EXPECT_LE(dq.max_lum, kExactTol);

  const auto s =
      make_test_frame(with_textured_light(make_builtin_scene("spheres")), 96, 96, one_sample());
  const RgbDiff dw = compare_rgb(s, {}), db = compare_rgb(s, {}, "wedge_blend");
  for (const auto& [name, d] : {std::pair{"wedges", dw}, std::pair{"wedge_blend", db}})
    std::printf("    textured spheres, %-11s mean(shadowed) rgb %.4f %.4f %.4f  max lum %.2e\n",
                name, d.mean_rgb_shadowed[0], d.mean_rgb_shadowed[1], d.mean_rgb_shadowed[2],
                d.max_lum);
  EXPECT_GT(db.shadowed, 1000);
  for (int c = 0; c < 3; ++c) EXPECT_LT(db.mean_rgb_shadowed[c], dw.mean_rgb_shadowed[c]) << c;
  EXPECT_LE(db.max_lum, kExactTol);
}

}  // namespace
}  // namespace penumbra
