// The exact reference's area sweep (shadows/exact/union_area.hpp) against Clipper's boolean
// difference of the uv square and the non-zero union, on hand-made and random polygon sets.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <vector>

#include "penumbra/core/rng.hpp"
#include "penumbra/shadows/exact/union_area.hpp"

namespace penumbra {
namespace {

using ClipperLib::cInt;
using ClipperLib::IntPoint;
using ClipperLib::Path;
using ClipperLib::Paths;

constexpr cInt kSide = static_cast<cInt>(kUvScale);

/// The square minus the non-zero union of `polygons`, by Clipper (Clipper units²).
double clipper_uncovered(const Paths& polygons) {
  ClipperLib::Clipper c;
  c.AddPath({IntPoint(0, 0), IntPoint(kSide, 0), IntPoint(kSide, kSide), IntPoint(0, kSide)},
            ClipperLib::ptSubject, true);
  c.AddPaths(polygons, ClipperLib::ptClip, true);
  Paths left;
  c.Execute(ClipperLib::ctDifference, left, ClipperLib::pftNonZero, ClipperLib::pftNonZero);
  return paths_area(left);
}

std::vector<UvEdge> edges_of(const Paths& polygons) {
  std::vector<DirectedEdge> edges;
  append_polygon_edges(polygons, edges);
  std::vector<UvEdge> uv;
  append_uv_edges(edges, uv);
  return uv;
}

/// A random convex polygon (3–8 vertices on an ellipse, positively oriented) inside the square,
/// or (outside = true) reaching up to half a side beyond it.
Path random_convex(Pcg32& rng, bool outside = false) {
  const int n = 3 + static_cast<int>(rng.next_float() * 6.0f);
  const double cx = 0.1 + 0.8 * rng.next_float(), cy = 0.1 + 0.8 * rng.next_float();
  const double rx = 0.02 + 0.3 * rng.next_float(), ry = 0.02 + 0.3 * rng.next_float();
  const double phase = 6.283185307179586 * rng.next_float();
  Path p;
  for (int k = 0; k < n; ++k) {
    const double a = phase + 6.283185307179586 * k / n;
    const double lo = outside ? -0.5 : 0.0, hi = outside ? 1.5 : 1.0;
    const double x = std::clamp(cx + (outside ? 2.0 : 1.0) * rx * std::cos(a), lo, hi);
    const double y = std::clamp(cy + (outside ? 2.0 : 1.0) * ry * std::sin(a), lo, hi);
    p.push_back(IntPoint(static_cast<cInt>(x * kUvScale), static_cast<cInt>(y * kUvScale)));
  }
  return p;
}

TEST(ExactUnionArea, HandMadeCases) {
  const cInt h = kSide / 2, q = kSide / 4;
  const double square = kUvScale * kUvScale;
  EXPECT_EQ(uncovered_square_area({}), square);
  // The whole square: nothing left, exactly.
  const Paths whole = {
      {IntPoint(0, 0), IntPoint(kSide, 0), IntPoint(kSide, kSide), IntPoint(0, kSide)}};
  EXPECT_EQ(uncovered_square_area(edges_of(whole)), 0.0);
  // Two overlapping squares [0, h]² and [q, q + h]²: union 2h² − (h − q)².
  const Paths two = {
      {IntPoint(0, 0), IntPoint(h, 0), IntPoint(h, h), IntPoint(0, h)},
      {IntPoint(q, q), IntPoint(q + h, q), IntPoint(q + h, q + h), IntPoint(q, q + h)}};
  const double hd = static_cast<double>(h), qd = static_cast<double>(q);
  EXPECT_NEAR(uncovered_square_area(edges_of(two)), square - (2 * hd * hd - (hd - qd) * (hd - qd)),
              1e-12 * square);
  // A triangle and its reversed copy: winding 0 everywhere, nothing covered.
  const Path tri = {IntPoint(0, 0), IntPoint(h, q), IntPoint(q, h)};
  const Path rev = {IntPoint(q, h), IntPoint(h, q), IntPoint(0, 0)};
  EXPECT_EQ(uncovered_square_area(edges_of({tri, rev})), square);
  // A star (self-crossing pentagram, winding 2 in the middle): every crossing splits a beam.
  Path star;
  for (int k = 0; k < 5; ++k) {
    const double a = 1.5707963267948966 + 2.0 * 6.283185307179586 * k / 5.0;
    star.push_back(IntPoint(static_cast<cInt>((0.5 + 0.4 * std::cos(a)) * kUvScale),
                            static_cast<cInt>((0.5 + 0.4 * std::sin(a)) * kUvScale)));
  }
  EXPECT_NEAR(uncovered_square_area(edges_of({star})) / square, clipper_uncovered({star}) / square,
              1e-8);
}

TEST(ExactUnionArea, MatchesClipperOnRandomOverlappingPolygons) {
  // Up to 40 overlapping convex polygons: many crossings per beam, shared vertex ordinates.
  Pcg32 rng(21, 22);
  const double square = kUvScale * kUvScale;
  double max_diff = 0.0;
  for (int trial = 0; trial < 300; ++trial) {
    Paths polygons;
    const int count = 1 + trial % 40;
    for (int k = 0; k < count; ++k) polygons.push_back(random_convex(rng));
    for (Path& p : polygons)
      if (ClipperLib::Area(p) < 0) std::reverse(p.begin(), p.end());
    const double sweep = uncovered_square_area(edges_of(polygons)) / square;
    const double clipper = clipper_uncovered(polygons) / square;
    max_diff = std::max(max_diff, std::abs(sweep - clipper));
    ASSERT_NEAR(sweep, clipper, 1e-8) << "trial " << trial;
  }
  std::printf("max |sweep - Clipper| %.3g of the square\n", max_diff);
}

TEST(ExactUnionArea, MeasuresOnlyTheSquareOfPolygonsReachingBeyondIt) {
  // Unclipped projections: only the field inside the square counts (parts left of it act on
  // u = 0, parts right, above and below of it on nothing).
  Pcg32 rng(23, 24);
  const double square = kUvScale * kUvScale;
  double max_diff = 0.0;
  int partial = 0;
  for (int trial = 0; trial < 300; ++trial) {
    Paths polygons;
    const int count = 1 + trial % 25;
    for (int k = 0; k < count; ++k) polygons.push_back(random_convex(rng, true));
    for (Path& p : polygons)
      if (ClipperLib::Area(p) < 0) std::reverse(p.begin(), p.end());
    const double sweep = uncovered_square_area(edges_of(polygons)) / square;
    const double clipper = clipper_uncovered(polygons) / square;
    partial += clipper > 1e-6 && clipper < 1.0 - 1e-6 ? 1 : 0;
    max_diff = std::max(max_diff, std::abs(sweep - clipper));
    ASSERT_NEAR(sweep, clipper, 1e-8) << "trial " << trial;
  }
  EXPECT_GT(partial, 200);
  std::printf("max |sweep - Clipper| %.3g of the square\n", max_diff);
}

}  // namespace
}  // namespace penumbra
