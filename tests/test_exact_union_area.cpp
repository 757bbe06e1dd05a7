// The exact reference's area sweep (shadows/exact/union_area.hpp) against Clipper's boolean
// difference of the uv square and the non-zero union, on hand-made and random polygon sets.
#include <gtest/gtest.h>

#include <algorithm>
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

// ---------------------------------------------------------------------------------------------
// The divided sweep: many edges in groups, outlines of partial unions merged pairwise.

/// The three edges of the positively oriented triangle (a, b, c), in uv × kUvScale.
void add_triangle(std::vector<UvEdge>& edges, DVec2 a, DVec2 b, DVec2 c) {
  if ((b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x) < 0.0) std::swap(b, c);
  for (const auto& [p, q] : {std::pair{a, b}, std::pair{b, c}, std::pair{c, a}})
    edges.push_back({p.x * kUvScale, p.y * kUvScale, q.x * kUvScale, q.y * kUvScale});
}

/// `count` thin random triangles ("twigs": 0.05–0.3 of the side long, 0.002–0.01 wide), some
/// reaching beyond the square, each its own group.
void add_twigs(std::vector<UvEdge>& edges, std::vector<uint32_t>& groups, Pcg32& rng, int count) {
  for (int k = 0; k < count; ++k) {
    const DVec2 c(-0.1 + 1.2 * rng.next_float(), -0.1 + 1.2 * rng.next_float());
    const double angle = 6.283185307179586 * rng.next_float();
    const double half = 0.5 * (0.05 + 0.25 * rng.next_float());
    const double width = 0.002 + 0.008 * rng.next_float();
    const DVec2 d(std::cos(angle), std::sin(angle)), n(-d.y, d.x);
    add_triangle(edges, c - half * d, c + half * d + width * n, c + half * d - width * n);
    const uint32_t group = groups.empty() ? 0 : groups.back() + 1;
    groups.insert(groups.end(), 3, group);
  }
}

/// `count` copies of one triangle scaled by 1.2–2.2 about a point outside it: the projections
/// of a stack of equal triangles seen from a receiver beside the stack. Every copy's edges cross
/// most others', so one sweep over all of them is quadratic.
void add_stack(std::vector<UvEdge>& edges, std::vector<uint32_t>& groups, int count) {
  const DVec2 centre(-0.4, 0.3), a(0.0, 0.0), b(0.5, 0.05), c(0.1, 0.45);
  for (int k = 0; k < count; ++k) {
    const double scale = 1.2 + k / static_cast<double>(count);
    add_triangle(edges, centre + scale * (a - centre), centre + scale * (b - centre),
                 centre + scale * (c - centre));
    groups.insert(groups.end(), 3, static_cast<uint32_t>(k));
  }
}

TEST(ExactUnionArea, DividedSweepEqualsOneSweepOnManyThinTriangles) {
  Pcg32 rng(31, 32);
  const double square = kUvScale * kUvScale;
  double max_diff = 0.0, min_uncovered = 1.0;
  for (int trial = 0; trial < 24; ++trial) {
    std::vector<UvEdge> edges;
    std::vector<uint32_t> groups;
    add_twigs(edges, groups, rng, 140 + 40 * trial);
    ASSERT_GT(edges.size(), kDivideAboveEdges);
    const double one = uncovered_square_area(edges) / square;
    const double divided = uncovered_square_area(edges, groups) / square;
    max_diff = std::max(max_diff, std::abs(one - divided));
    min_uncovered = std::min(min_uncovered, one);
    ASSERT_NEAR(divided, one, 1e-12) << "trial " << trial;
  }
  EXPECT_GT(min_uncovered, 0.0);  // the twigs never cover the whole square: every sweep ran
  std::printf("max |divided - one sweep| %.3g of the square\n", max_diff);
}

TEST(ExactUnionArea, GroupsKeepAHoleWithItsOutline) {
  // A square ring (outer loop counter-clockwise, inner clockwise: one group) and twigs, some in
  // its hole. Split from its outer loop, the inner one alone would have winding −1.
  Pcg32 rng(33, 34);
  const double square = kUvScale * kUvScale;
  std::vector<UvEdge> edges;
  std::vector<uint32_t> groups;
  add_twigs(edges, groups, rng, 150);
  const uint32_t ring = groups.back() + 1;
  const auto loop = [&](double lo, double hi, bool reversed) {
    DVec2 c[4] = {{lo, lo}, {hi, lo}, {hi, hi}, {lo, hi}};
    if (reversed) std::reverse(c, c + 4);
    for (int k = 0; k < 4; ++k) {
      const DVec2 p = c[k], q = c[(k + 1) % 4];
      edges.push_back({p.x * kUvScale, p.y * kUvScale, q.x * kUvScale, q.y * kUvScale});
      groups.push_back(ring);
    }
  };
  loop(0.1, 0.9, false);
  loop(0.3, 0.7, true);
  add_twigs(edges, groups, rng, 150);
  const double one = uncovered_square_area(edges) / square;
  EXPECT_GT(one, 0.1);
  EXPECT_NEAR(uncovered_square_area(edges, groups) / square, one, 1e-12);
}

TEST(ExactUnionArea, OutlineOfTheUnionHasItsArea) {
  Pcg32 rng(35, 36);
  const double square = kUvScale * kUvScale;
  std::vector<UvEdge> edges, outline;
  std::vector<uint32_t> groups;
  add_stack(edges, groups, 200);
  add_twigs(edges, groups, rng, 100);
  const double one = uncovered_square_area(edges);
  EXPECT_NEAR(covered_outline(edges, outline) / square, one / square, 1e-15);
  EXPECT_NEAR(uncovered_square_area(outline) / square, one / square, 1e-12);
  EXPECT_LT(outline.size(), edges.size() * 17 / 20);  // measured 713 of 900: inner edges gone
  // Its field is 1 on the union, like a positively oriented polygon's: added to other polygons'
  // edges it unites with them (a field of −1 would cancel theirs where they overlap).
  std::vector<UvEdge> more, with_outline = outline, with_edges = edges;
  add_twigs(more, groups, rng, 200);
  with_outline.insert(with_outline.end(), more.begin(), more.end());
  with_edges.insert(with_edges.end(), more.begin(), more.end());
  EXPECT_NEAR(uncovered_square_area(with_outline) / square,
              uncovered_square_area(with_edges) / square, 1e-12);
  std::printf("outline: %zu of %zu edges\n", outline.size(), edges.size());
}

TEST(ExactUnionArea, StackedCopiesCostNLogNNotNSquared) {
  // The work (edges crossing each beam, summed) for 4× the copies: one sweep grows about 16×
  // (every copy's edges in every beam); divided, each level of the merge tree costs about the
  // outlines' size, O(N), over log2(edges / kLeafEdges) levels.
  const double square = kUvScale * kUvScale;
  SweepWork one_work[2], divided_work[2];
  const int counts[2] = {500, 2000};
  for (int i = 0; i < 2; ++i) {
    std::vector<UvEdge> edges;
    std::vector<uint32_t> groups;
    add_stack(edges, groups, counts[i]);
    const double one = uncovered_square_area(edges, &one_work[i]);
    const double divided = uncovered_square_area(edges, groups, &divided_work[i]);
    EXPECT_NEAR(divided / square, one / square, 1e-12);
    EXPECT_GT(one / square, 0.01);
  }
  const double one_ratio =
      static_cast<double>(one_work[1].edge_beams) / static_cast<double>(one_work[0].edge_beams);
  const double ratio = static_cast<double>(divided_work[1].edge_beams) /
                       static_cast<double>(divided_work[0].edge_beams);
  std::printf("work 500 -> 2000 copies: one sweep %.1fx (%llu), divided %.2fx (%llu)\n", one_ratio,
              static_cast<unsigned long long>(one_work[1].edge_beams), ratio,
              static_cast<unsigned long long>(divided_work[1].edge_beams));
  EXPECT_GT(one_ratio, 12.0);
  const double leaves = static_cast<double>(kLeafEdges);
  EXPECT_LE(ratio, 4.0 * std::log2(6000.0 / leaves) / std::log2(1500.0 / leaves));  // 5.44
}

}  // namespace
}  // namespace penumbra
