// The caster groups of `wedges --set wedges.overlap=true` and `wedge_blend` (wedges/pass.hpp):
// light-facing patches, each bounded by its silhouette loops from the light centre [Assarsson 2003
// IV §5.1; Forest 2008 §3.2, Algorithm 4 line 1]. Whatever the grouping, the groups must add up to
// the whole: per pixel the groups' hard counts sum to the layered count of the meshes, and the
// groups' silhouette edges carry the same signed weight per edge as the meshes'.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdio>
#include <map>
#include <utility>

#include "penumbra/render/receivers.hpp"
#include "penumbra/scene/model_paths.hpp"
#include "penumbra/shadows/wedges/pass.hpp"
#include "penumbra/shadows/wedges/shadow_volume.hpp"
#include "support/frame_helpers.hpp"

namespace penumbra {
namespace {

using namespace wedge_pass;

/// A sheet folded twice (a "Z" seen from the side), one connected open mesh: panel A at y = 1
/// facing up, panel B folded back under it (facing down, away from a light above), panel C at
/// y = 0.5 facing up again, half under A. Seen from above, A and C overlap: two light-facing
/// patches and one back-facing one.
Mesh z_fold() {
  Mesh m;
  m.name = "z_fold";
  const float ys[4] = {1.0f, 1.0f, 0.5f, 0.5f};
  const float zs[4] = {-1.0f, 1.0f, -0.5f, 2.0f};
  for (int r = 0; r < 4; ++r)
    for (float x : {-1.0f, 1.0f}) m.positions.push_back(Vec3(x, ys[r], zs[r]));
  for (uint32_t r = 0; r < 3; ++r) {
    const uint32_t a = 2 * r, b = a + 1, c = a + 2, d = a + 3;
    m.triangles.push_back({{a, c, b}});
    m.triangles.push_back({{b, c, d}});
  }
  return m;
}

Scene z_fold_scene() {
  Scene s = make_builtin_scene("quad");
  s.meshes[1] = z_fold();
  s.lights[0].center = Vec3(0.2f, 3.0f, -0.3f);
  return s;
}

/// The oracle: every caster mesh whole, with its layer count (the shadow_volume count / layers).
Casters whole_meshes(const Scene& s) {
  Casters c;
  for (const Mesh& mesh : s.meshes) {
    if (!mesh.casts_shadows || mesh.triangles.empty()) continue;
    c.meshes.push_back(&mesh);
    c.edges.push_back(build_mesh_edges(mesh));
    c.layers.push_back(mesh_layers(c.edges.back()));
  }
  return c;
}

struct Sums {
  size_t groups = 0;
  size_t count_mismatches = 0;  // pixels where Σ group counts ≠ layered count
  size_t shadowed = 0;          // pixels with a nonzero layered count
  size_t edge_mismatches = 0;   // edges whose summed signed weights differ
};

/// Signed weight per directed position pair (from < to lexicographically, sign flipped otherwise).
std::map<std::pair<std::array<float, 3>, std::array<float, 3>>, double> edge_weights(
    const std::vector<WedgeEdge>& edges) {
  std::map<std::pair<std::array<float, 3>, std::array<float, 3>>, double> w;
  for (const WedgeEdge& e : edges) {
    std::array<float, 3> a{float(e.from.x), float(e.from.y), float(e.from.z)};
    std::array<float, 3> b{float(e.to.x), float(e.to.y), float(e.to.z)};
    w[a < b ? std::make_pair(a, b) : std::make_pair(b, a)] += a < b ? e.weight : -e.weight;
  }
  return w;
}

Sums compare_groupings(Scene scene, int size) {
  const test::TestFrame t =
      test::make_test_frame(std::move(scene), size, size, test::centre_sample());
  const Scene& s = *t.scene;
  const Light& light = s.lights[0];
  const ShadowContext ctx{
      s, nullptr, t.frame->gbuffer(), 0, light, t.frame->samples(), t.frame->receivers(0), false};
  const Vec3 centre = hard_shadow_point(light);
  const Casters whole = whole_meshes(s);
  const Casters patches = make_casters(s, centre);
  Sums r;
  r.groups = patches.meshes.size();

  const Image<float> layered = layered_counts(ctx, whole, centre);
  const GroupCounts gc = group_counts(ctx, patches, centre);
  for (size_t i = 0; i < layered.size(); ++i) {
    double sum = 0.0;
    for (uint32_t k = gc.begin[i]; k < gc.begin[i + 1]; ++k) sum += gc.value[k];
    r.shadowed += layered[i] != 0.0f;
    r.count_mismatches += std::abs(sum - layered[i]) > 1e-6;
  }

  auto a = edge_weights(silhouette_edges(whole, centre));
  auto b = edge_weights(silhouette_edges(patches, centre));
  for (const auto& [k, w] : a) r.edge_mismatches += std::abs(w - b[k]) > 1e-9;
  for (const auto& [k, w] : b) r.edge_mismatches += std::abs(w - a[k]) > 1e-9;
  return r;
}

void expect_groups_add_up(const char* what, Scene scene, size_t min_groups) {
  const Sums r = compare_groupings(std::move(scene), 64);
  std::printf("    %-22s groups %zu  shadowed %zu  count mismatches %zu  edge mismatches %zu\n",
              what, r.groups, r.shadowed, r.count_mismatches, r.edge_mismatches);
  EXPECT_GE(r.groups, min_groups) << what;
  EXPECT_GT(r.shadowed, 0u) << what;
  EXPECT_EQ(r.count_mismatches, 0u) << what;
  EXPECT_EQ(r.edge_mismatches, 0u) << what;
}

TEST(WedgeGroups, PatchesAddUpToTheMeshesOnBuiltinScenes) {
  // quad: ground + occluder sheet; spheres: one patch per sphere (+ ground); fence: open slats.
  expect_groups_add_up("quad", make_builtin_scene("quad"), 2);
  expect_groups_add_up("spheres", make_builtin_scene("spheres"), 4);
  expect_groups_add_up("fence", make_builtin_scene("fence"), 2);
  expect_groups_add_up("default", make_builtin_scene("default"), 2);
}

TEST(WedgeGroups, ZFoldSplitsIntoItsThreePanels) {
  const Scene s = z_fold_scene();
  const Casters patches = make_casters(s, s.lights[0].center);
  const Casters whole = whole_meshes(s);
  // ground (1 patch) + the three panels of the one connected fold.
  EXPECT_EQ(whole.meshes.size(), 2u);
  EXPECT_EQ(patches.meshes.size(), 4u);
  for (int layers : patches.layers) EXPECT_EQ(layers, 1);
  expect_groups_add_up("z fold", s, 4);
}

TEST(WedgeGroups, DegenerateTopologyAddsUp) {
  Scene s = make_builtin_scene("quad");
  s.meshes[1] = test::open_flipped_sphere();
  expect_groups_add_up("open flipped sphere", std::move(s), 3);
}

/// A closed mesh with a hole (one triangle missing, facing away from the light) still counts as a
/// solid for the wedge methods (solid_for_wedges): the same light-facing patches, and the same
/// `wedges` answer, as the closed mesh. Counted as an open sheet it would have two layers
/// everywhere and every silhouette edge's coverage twice.
TEST(WedgeGroups, MeshWithAHoleCountsAsASolid) {
  Scene closed = make_builtin_scene("spheres");
  Scene holed = closed;
  Mesh& m = holed.meshes[1];
  size_t lowest = 0;
  float lowest_y = kInfinity;
  for (size_t t = 0; t < m.triangles.size(); ++t) {
    const float y = m.vertex(t, 0).y + m.vertex(t, 1).y + m.vertex(t, 2).y;
    if (y < lowest_y) lowest_y = y, lowest = t;
  }
  m.triangles.erase(m.triangles.begin() + static_cast<std::ptrdiff_t>(lowest));
  const MeshEdges edges = build_mesh_edges(m);
  ASSERT_EQ(edges.boundary_edges, 3u);
  EXPECT_FALSE(edges.closed_manifold());
  EXPECT_TRUE(solid_for_wedges(m, edges));
  const Vec3 centre = closed.lights[0].center;
  EXPECT_EQ(make_casters(holed, centre).meshes.size(), make_casters(closed, centre).meshes.size());

  const test::TestFrame tc =
      test::make_test_frame(std::move(closed), 64, 64, test::centre_sample());
  const test::TestFrame th = test::make_test_frame(std::move(holed), 64, 64, test::centre_sample());
  const MethodResult rc = tc.run("wedges"), rh = th.run("wedges");
  const Image<float>& vc = rc.per_light[0].lit;
  const Image<float>& vh = rh.per_light[0].lit;
  double max_diff = 0.0;
  for (size_t i = 0; i < vc.size(); ++i)
    max_diff = std::max(max_diff, std::abs(static_cast<double>(vc[i]) - vh[i]));
  std::printf("    spheres with a hole vs closed, wedges: max |dV| %.2e\n", max_diff);
  EXPECT_LE(max_diff, 1e-6);
}

TEST(WedgeGroups, LightInsideAClosedMeshKeepsTheMeshWhole) {
  // Nothing of the box faces a light inside it: the mesh stays one group, and every crossing
  // counts (one layer: a segment from outside crosses the box once, which blocks it).
  Scene s = make_builtin_scene("quad");
  s.meshes.push_back(make_box(s.lights[0].center, Vec3(0.3f)));
  const Casters patches = make_casters(s, s.lights[0].center);
  ASSERT_FALSE(patches.layers.empty());
  EXPECT_EQ(patches.layers.back(), 1);
  EXPECT_EQ(patches.meshes.back(), &s.meshes.back());
}

TEST(WedgeGroups, BunnyHasOnePatchPerLightFacingPart) {
  if (!find_model("bunny00.off")) GTEST_SKIP() << "bunny not fetched: run scripts/fetch-models.sh";
  expect_groups_add_up("bunny", make_builtin_scene("bunny"), 3);
}

}  // namespace
}  // namespace penumbra
