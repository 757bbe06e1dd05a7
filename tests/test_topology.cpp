// Edge topology: boundary, non-manifold and inconsistently oriented edges.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <map>
#include <random>
#include <tuple>
#include <utility>

#include "penumbra/scene/shapes.hpp"
#include "penumbra/scene/topology.hpp"
#include "penumbra/scene/weld.hpp"

namespace penumbra {
namespace {

Mesh triangles(std::vector<Vec3> positions, std::vector<Triangle> tris) {
  Mesh m;
  m.positions = std::move(positions);
  m.triangles = std::move(tris);
  return m;
}

/// The same mesh with every triangle given its own three vertices (no sharing).
Mesh unshared(const Mesh& in) {
  Mesh out;
  for (size_t t = 0; t < in.triangle_count(); ++t) {
    const uint32_t base = static_cast<uint32_t>(out.positions.size());
    for (int c = 0; c < 3; ++c) out.positions.push_back(in.vertex(t, c));
    out.triangles.push_back({{base, base + 1, base + 2}});
  }
  return out;
}

TEST(Topology, BoxIsClosedManifold) {
  const MeshTopology t = analyze_topology(make_box(Vec3(0.1f, 0.2f, 0.3f), Vec3(0.5f, 1.0f, 2.0f)));
  EXPECT_EQ(t.edges, 18u);  // 12 triangles * 3 / 2
  EXPECT_EQ(t.boundary_edges, 0u);
  EXPECT_EQ(t.non_manifold_edges, 0u);
  EXPECT_EQ(t.inconsistent_edges, 0u);
  EXPECT_TRUE(t.closed_manifold);
}

TEST(Topology, SphereIsClosedManifold) {
  for (const auto& [rings, segments] : {std::pair{2, 3}, std::pair{8, 16}, std::pair{16, 32}}) {
    const Mesh m = make_sphere(Vec3(0.0f, 1.0f, 0.0f), 0.7f, rings, segments);
    const MeshTopology t = analyze_topology(m);
    EXPECT_TRUE(t.closed_manifold) << rings << "x" << segments;
    EXPECT_EQ(t.boundary_edges + t.non_manifold_edges + t.inconsistent_edges, 0u);
    // Euler characteristic of a sphere: V - E + F = 2.
    EXPECT_EQ(static_cast<long>(m.positions.size()) - static_cast<long>(t.edges) +
                  static_cast<long>(m.triangle_count()),
              2);
  }
}

TEST(Topology, QuadHasFourBoundaryEdges) {
  const MeshTopology t = analyze_topology(make_quad(Vec3(0.0f), Vec3(1, 0, 0), Vec3(0, 0, 1)));
  EXPECT_EQ(t.edges, 5u);
  EXPECT_EQ(t.boundary_edges, 4u);
  EXPECT_EQ(t.non_manifold_edges, 0u);
  EXPECT_EQ(t.inconsistent_edges, 0u);
  EXPECT_FALSE(t.closed_manifold);
}

TEST(Topology, ThreeTrianglesSharingOneEdgeAreNonManifold) {
  // A "book" of three pages hinged on the edge (0,0,0)-(0,1,0).
  const Mesh m = triangles({{0, 0, 0}, {0, 1, 0}, {1, 0, 0}, {0, 0, 1}, {-1, 0, 0}},
                           {{{0, 1, 2}}, {{1, 0, 3}}, {{0, 1, 4}}});
  const MeshTopology t = analyze_topology(m);
  EXPECT_EQ(t.edges, 7u);
  EXPECT_EQ(t.non_manifold_edges, 1u);
  EXPECT_EQ(t.boundary_edges, 6u);
  EXPECT_EQ(t.inconsistent_edges, 0u);
  EXPECT_FALSE(t.closed_manifold);
}

TEST(Topology, FlippedTriangleIsInconsistent) {
  // Two triangles of a square traversing their shared diagonal in the same direction.
  const Mesh pair =
      triangles({{0, 0, 0}, {1, 0, 0}, {1, 0, 1}, {0, 0, 1}}, {{{0, 1, 2}}, {{0, 3, 2}}});
  const MeshTopology t = analyze_topology(pair);
  EXPECT_EQ(t.edges, 5u);
  EXPECT_EQ(t.inconsistent_edges, 1u);
  EXPECT_EQ(t.boundary_edges, 4u);
  EXPECT_FALSE(t.closed_manifold);

  // One flipped triangle in a closed box: its three edges disagree with their neighbours.
  Mesh box = make_box(Vec3(0.0f), Vec3(1.0f));
  std::swap(box.triangles[5].v[1], box.triangles[5].v[2]);
  const MeshTopology b = analyze_topology(box);
  EXPECT_EQ(b.inconsistent_edges, 3u);
  EXPECT_EQ(b.boundary_edges, 0u);
  EXPECT_EQ(b.non_manifold_edges, 0u);
  EXPECT_FALSE(b.closed_manifold);
}

TEST(Topology, WeldsVerticesByExactPosition) {
  // Triangle soup (as a loader without vertex joining produces) is still a closed box.
  const Mesh soup = unshared(make_box(Vec3(0.0f), Vec3(1.0f)));
  EXPECT_EQ(soup.positions.size(), 36u);
  EXPECT_TRUE(analyze_topology(soup).closed_manifold);

  // No tolerance: moving one soup vertex by one ulp opens a crack (its two edges become two
  // boundary edges each).
  Mesh cracked = soup;
  cracked.positions[0].x = std::nextafter(cracked.positions[0].x, 10.0f);
  const MeshTopology t = analyze_topology(cracked);
  EXPECT_FALSE(t.closed_manifold);
  EXPECT_EQ(t.boundary_edges, 4u);

  // -0.0 and +0.0 are the same position.
  const Mesh zeros = triangles({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {-0.0f, 0, 0}, {0, -0.0f, 1}},
                               {{{0, 1, 2}}, {{3, 2, 4}}});
  EXPECT_EQ(analyze_topology(zeros).edges, 5u);
}

TEST(Topology, DegenerateAndEmptyMeshes) {
  EXPECT_FALSE(analyze_topology(Mesh{}).closed_manifold);
  EXPECT_EQ(analyze_topology(Mesh{}).edges, 0u);
  // A triangle with two welded corners has no edges to count; out-of-range indices are skipped.
  const Mesh m = triangles({{0, 0, 0}, {1, 0, 0}, {0, 0, 0}}, {{{0, 1, 2}}, {{0, 1, 7}}});
  const MeshTopology t = analyze_topology(m);
  EXPECT_EQ(t.edges, 0u);
  EXPECT_FALSE(t.closed_manifold);
}

/// weld_positions, the one welding rule every mesh analysis shares: representatives are the first
/// vertex at each bit-identical position (−0 = +0), against a brute-force map on 20 000 vertices
/// drawn from 300 positions, some of them ±0 and one ulp apart.
TEST(Weld, FirstVertexAtEachBitIdenticalPosition) {
  std::mt19937 rng(7);
  std::vector<Vec3> pool;
  std::uniform_real_distribution<float> coord(-2.0f, 2.0f);
  for (int i = 0; i < 100; ++i) {
    const Vec3 p(coord(rng), coord(rng), coord(rng));
    pool.push_back(p);
    pool.push_back(Vec3(std::nextafter(p.x, 10.0f), p.y, p.z));  // one ulp away: distinct
    pool.push_back(Vec3(i % 2 ? -0.0f : 0.0f, 0.5f, i % 3 ? -0.0f : 0.0f));  // all one point
  }
  std::uniform_int_distribution<size_t> pick(0, pool.size() - 1);
  std::vector<Vec3> positions(20000);
  for (Vec3& p : positions) p = pool[pick(rng)];
  const std::vector<uint32_t> weld = weld_positions(positions);
  ASSERT_EQ(weld.size(), positions.size());
  std::map<std::tuple<uint32_t, uint32_t, uint32_t>, uint32_t> first;
  size_t groups = 0;
  for (uint32_t i = 0; i < positions.size(); ++i) {
    auto bits = [](float x) {
      const float y = x + 0.0f;
      uint32_t b = 0;
      std::memcpy(&b, &y, sizeof b);
      return b;
    };
    const auto key =
        std::make_tuple(bits(positions[i].x), bits(positions[i].y), bits(positions[i].z));
    const auto [it, added] = first.try_emplace(key, i);
    groups += added;
    ASSERT_EQ(weld[i], it->second) << "vertex " << i;
  }
  EXPECT_EQ(groups, 201u);  // 100 points, their 100 ulp neighbours, one (±0, 0.5, ±0)
  EXPECT_TRUE(weld_positions({}).empty());
}

}  // namespace
}  // namespace penumbra
