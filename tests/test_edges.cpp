// Edge adjacency, silhouettes w.r.t. a point and a whole light, and silhouette loops.
#include <gtest/gtest.h>

#include <algorithm>
#include <map>
#include <numeric>
#include <set>

#include "penumbra/scene/edges.hpp"
#include "penumbra/scene/shapes.hpp"
#include "penumbra/scene/silhouettes.hpp"
#include "penumbra/scene/topology.hpp"

namespace penumbra {
namespace {

/// Σ outgoing − Σ incoming multiplicity at every vertex is zero (the silhouette is a cycle).
void expect_balanced(const std::vector<SilhouetteEdge>& sil) {
  std::map<uint32_t, int> balance;
  for (const SilhouetteEdge& s : sil) {
    balance[s.from] += s.multiplicity;
    balance[s.to] -= s.multiplicity;
  }
  for (const auto& [v, b] : balance) EXPECT_EQ(b, 0) << "vertex " << v;
}

/// Every loop is chained and closed.
void expect_closed_loops(const std::vector<SilhouetteEdge>& sil,
                         const std::vector<std::vector<uint32_t>>& loops) {
  for (const auto& loop : loops) {
    ASSERT_FALSE(loop.empty());
    for (size_t k = 0; k < loop.size(); ++k)
      EXPECT_EQ(sil[loop[k]].to, sil[loop[(k + 1) % loop.size()]].from);
  }
}

TEST(Edges, BoxIsClosedManifoldAndAgreesWithTopology) {
  const Mesh box = make_box(Vec3(0.1f, 0.2f, 0.3f), Vec3(0.5f, 1.0f, 2.0f));
  const MeshEdges e = build_mesh_edges(box);
  EXPECT_EQ(e.edges.size(), 18u);
  EXPECT_TRUE(e.closed_manifold());
  const MeshTopology t = analyze_topology(box);
  EXPECT_EQ(e.edges.size(), t.edges);
  for (const MeshEdge& edge : e.edges) {
    ASSERT_EQ(edge.face_count, 2u);
    EXPECT_EQ(e.edge_faces[edge.face_begin].sign + e.edge_faces[edge.face_begin + 1].sign, 0);
  }
  // face_edges points back at edges containing the face.
  for (size_t f = 0; f < e.faces.size(); ++f)
    for (int c = 0; c < 3; ++c) {
      const MeshEdge& edge = e.edges[e.face_edges[f][c]];
      bool found = false;
      for (uint32_t k = 0; k < edge.face_count; ++k)
        found |= e.edge_faces[edge.face_begin + k].face == f;
      EXPECT_TRUE(found);
    }
}

TEST(Edges, UnsharedQuadVerticesAreWeldedByPosition) {
  Mesh quad = make_quad(Vec3(0.0f), Vec3(1, 0, 0), Vec3(0, 0, 1));
  // Give the second triangle its own copies of the vertices.
  Mesh split = quad;
  split.positions.clear();
  split.triangles.clear();
  for (const Triangle& t : quad.triangles) {
    const uint32_t base = static_cast<uint32_t>(split.positions.size());
    for (int c = 0; c < 3; ++c) split.positions.push_back(quad.positions[t.v[c]]);
    split.triangles.push_back({{base, base + 1, base + 2}});
  }
  const MeshEdges e = build_mesh_edges(split);
  EXPECT_EQ(e.edges.size(), 5u);
  EXPECT_EQ(e.boundary_edges, 4u);
  EXPECT_EQ(e.manifold_edges, 1u);
  // An open quad: every boundary edge is a silhouette of multiplicity 1, one loop of 4 edges.
  const auto sil = point_silhouette(split, e, Vec3(0.2f, 2.0f, 0.1f));
  ASSERT_EQ(sil.size(), 4u);
  for (const auto& s : sil) EXPECT_EQ(s.multiplicity, 1);
  const auto loops = silhouette_loops(sil);
  ASSERT_EQ(loops.size(), 1u);
  EXPECT_EQ(loops[0].size(), 4u);
  expect_closed_loops(sil, loops);
}

TEST(Silhouettes, SpherePointSilhouetteIsOneLoop) {
  const Mesh sphere = make_sphere(Vec3(0.0f), 1.0f, 16, 32);
  const MeshEdges e = build_mesh_edges(sphere);
  ASSERT_TRUE(e.closed_manifold());
  for (const Vec3 light :
       {Vec3(0.3f, 4.0f, 0.2f), Vec3(5.0f, 0.1f, -2.0f), Vec3(-1.5f, -1.2f, 1.1f)}) {
    const auto sil = point_silhouette(sphere, e, light);
    ASSERT_GE(sil.size(), 16u);
    for (const auto& s : sil) EXPECT_EQ(s.multiplicity, 2);  // one front and one back face
    expect_balanced(sil);
    const auto loops = silhouette_loops(sil);
    ASSERT_EQ(loops.size(), 1u) << "light " << light.x << "," << light.y << "," << light.z;
    EXPECT_EQ(loops[0].size(), sil.size());
    expect_closed_loops(sil, loops);
    // Each silhouette edge has one face toward the light and one away.
    const auto sides = face_sides(sphere, e, light);
    for (const auto& s : sil) {
      const MeshEdge& edge = e.edges[s.edge];
      EXPECT_EQ(
          sides[e.edge_faces[edge.face_begin].face] * sides[e.edge_faces[edge.face_begin + 1].face],
          -1);
    }
  }
}

TEST(Silhouettes, WholeLightSilhouetteContainsPointSilhouettes) {
  const Mesh sphere = make_sphere(Vec3(0.0f), 1.0f, 12, 24);
  const MeshEdges e = build_mesh_edges(sphere);
  std::vector<Light> lights(3);
  lights[0].shape = LightShape::rect;
  lights[0].center = Vec3(0.2f, 3.0f, 0.1f);
  lights[0].edge_u = Vec3(1.0f, 0, 0);
  lights[0].edge_v = Vec3(0, 0, 1.0f);
  lights[1].shape = LightShape::disk;
  lights[1].center = Vec3(2.5f, 1.0f, 0.0f);
  lights[1].normal = glm::normalize(Vec3(-1, -0.3f, 0));
  lights[1].radius = 0.6f;
  lights[2].shape = LightShape::sphere;
  lights[2].center = Vec3(-2.0f, 2.0f, 1.0f);
  lights[2].radius = 0.5f;
  for (const Light& light : lights) {
    const auto whole = light_silhouette_edges(sphere, e, light);
    const std::set<uint32_t> whole_set(whole.begin(), whole.end());
    // Points of the light: centre, and points on its boundary.
    std::vector<Vec3> points = {light.center};
    if (light.shape == LightShape::rect) {
      for (float u : {-0.5f, 0.5f})
        for (float v : {-0.5f, 0.5f})
          points.push_back(light.center + u * light.edge_u + v * light.edge_v);
    } else {
      Vec3 t, b;
      orthonormal_basis(light.shape == LightShape::disk ? light.normal : Vec3(0, 1, 0), t, b);
      for (int k = 0; k < 8; ++k) {
        const float a = static_cast<float>(k) * 0.785398f;
        points.push_back(light.center + 0.99f * light.radius * (std::cos(a) * t + std::sin(a) * b));
      }
    }
    size_t largest = 0;
    for (const Vec3& p : points) {
      const auto sil = point_silhouette(sphere, e, p);
      largest = std::max(largest, sil.size());
      for (const auto& s : sil) EXPECT_TRUE(whole_set.count(s.edge)) << "edge " << s.edge;
    }
    EXPECT_GT(whole.size(), largest);  // an area light's silhouette is wider than any point's
  }
  // A point light's whole-light silhouette is its point silhouette.
  Light point;
  point.shape = LightShape::point;
  point.center = Vec3(0.3f, 3.0f, 0.2f);
  EXPECT_EQ(light_silhouette_edges(sphere, e, point).size(),
            point_silhouette(sphere, e, point.center).size());
}

TEST(Silhouettes, NonManifoldAndInconsistentMeshesStayBalanced) {
  // A box with a fin: two extra triangles sharing one box edge (non-manifold: 4 faces), one of
  // them flipped, plus one box triangle flipped (inconsistent edges).
  Mesh m = make_box(Vec3(0.0f), Vec3(0.5f));
  const MeshEdges box_edges = build_mesh_edges(m);
  const MeshEdge& shared = box_edges.edges[0];
  const uint32_t a = shared.v0, b = shared.v1;
  const Vec3 mid = 0.5f * (m.positions[a] + m.positions[b]);
  m.positions.push_back(mid + Vec3(0.0f, 0.9f, 0.4f));
  m.positions.push_back(mid + Vec3(0.7f, -0.3f, 0.0f));
  const uint32_t c = static_cast<uint32_t>(m.positions.size() - 2), d = c + 1;
  m.triangles.push_back({{a, b, c}});
  m.triangles.push_back({{a, b, d}});
  std::swap(m.triangles[3].v[1], m.triangles[3].v[2]);
  const MeshEdges e = build_mesh_edges(m);
  EXPECT_EQ(e.non_manifold_edges, 1u);
  EXPECT_GT(e.inconsistent_edges, 0u);
  EXPECT_GT(e.boundary_edges, 0u);
  EXPECT_FALSE(e.closed_manifold());
  const MeshTopology t = analyze_topology(m);
  EXPECT_EQ(e.boundary_edges, t.boundary_edges);
  EXPECT_EQ(e.non_manifold_edges, t.non_manifold_edges);
  EXPECT_EQ(e.inconsistent_edges, t.inconsistent_edges);
  for (const Vec3 light :
       {Vec3(0.2f, 3.0f, 0.1f), Vec3(-2.0f, 0.3f, 1.0f), Vec3(0.1f, -2.0f, 3.0f)}) {
    const auto sil = point_silhouette(m, e, light);
    ASSERT_FALSE(sil.empty());
    expect_balanced(sil);
    const auto loops = silhouette_loops(sil);
    expect_closed_loops(sil, loops);
    size_t total = 0;
    for (const auto& l : loops) total += l.size();
    int g = 0;
    for (const auto& s : sil) g = std::gcd(g, s.multiplicity);
    size_t copies = 0;
    for (const auto& s : sil) copies += static_cast<size_t>(s.multiplicity / g);
    EXPECT_EQ(total, copies);  // every edge copy in exactly one loop
  }
}

}  // namespace
}  // namespace penumbra
