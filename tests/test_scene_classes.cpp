// The built-in scene classes (nest, garden, herd): sizes, seeded determinism, herd's two forms,
// and the sample-exact methods' masks equal to raytrace's on a small frame of each.
#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>
#include <string>

#include "penumbra/scene/model_paths.hpp"
#include "penumbra/scene/scene_classes.hpp"
#include "penumbra/scene/topology.hpp"
#include "support/frame_helpers.hpp"
#include "support/mask_agreement.hpp"

namespace penumbra {
namespace {

/// FNV-1a over the bytes of every position of every mesh, in order.
uint64_t position_hash(const Scene& s) {
  uint64_t h = 1469598103934665603ull;
  for (const Mesh& m : s.meshes) {
    for (const Vec3& p : m.positions) {
      unsigned char bytes[sizeof(float) * 3];
      std::memcpy(bytes, &p.x, sizeof(float));
      std::memcpy(bytes + sizeof(float), &p.y, sizeof(float));
      std::memcpy(bytes + 2 * sizeof(float), &p.z, sizeof(float));
      for (unsigned char b : bytes) h = (h ^ b) * 1099511628211ull;
    }
  }
  return h;
}

/// Triangles of every mesh but the ground.
size_t occluder_triangles(const Scene& s) {
  size_t n = 0;
  for (const Mesh& m : s.meshes)
    if (m.name != "ground") n += m.triangle_count();
  return n;
}

TEST(SceneClasses, NestIsManyDisconnectedTwigs) {
  Scene s = make_builtin_scene("nest");
  EXPECT_EQ(validate_scene(s), 0u);
  EXPECT_GE(occluder_triangles(s), 100000u);
  ASSERT_EQ(s.meshes.size(), 2u);
  const Mesh& twigs = s.meshes[1];
  EXPECT_EQ(twigs.positions.size(), twigs.triangle_count());  // 6 vertices, 6 triangles a twig
  // Open tubes: each twig's two open ends are three boundary edges each, no edge is shared by
  // two twigs.
  const MeshTopology t = analyze_topology(twigs);
  EXPECT_EQ(t.boundary_edges, twigs.triangle_count());
  EXPECT_EQ(t.non_manifold_edges, 0u);
  EXPECT_GE(s.bounds().lo.y, 0.0f);
}

TEST(SceneClasses, GardenIsAlphaTexturedLeavesOnStems) {
  Scene s = make_builtin_scene("garden");
  EXPECT_EQ(validate_scene(s), 0u);
  EXPECT_GE(occluder_triangles(s), 200000u);
  size_t textured = 0;
  for (const Mesh& m : s.meshes)
    if (s.material_of(m).alpha_texture >= 0) textured += m.triangle_count();
  EXPECT_GE(textured, 200000u);
  // The leaf mask covers about half its card (measured 0.516): the cards are perforated.
  ASSERT_EQ(s.textures.size(), 1u);
  double covered = 0.0;
  for (float a : s.textures[0].texels) covered += a;
  covered /= static_cast<double>(s.textures[0].texels.size());
  EXPECT_NEAR(covered, 0.516, 0.01);
  EXPECT_GE(s.bounds().lo.y, 0.0f);
}

TEST(SceneClasses, HerdIsDenseClosedModelsEitherWay) {
  const bool fetched = herd_models_fetched();
  Scene procedural = make_herd_scene(kSceneClassSeed, HerdSource::procedural);
  EXPECT_EQ(validate_scene(procedural), 0u);
  EXPECT_EQ(occluder_triangles(procedural), 3u * 57120u + 3u * 57600u);
  for (const Mesh& m : procedural.meshes) {
    if (m.name == "ground") continue;
    SCOPED_TRACE(m.name);
    EXPECT_TRUE(analyze_topology(m).closed_manifold);
    EXPECT_GE(m.bounds().lo.y, 0.0f);
  }
  EXPECT_EQ(builtin_scene_origin("herd").find("procedural") == 0, !fetched)
      << builtin_scene_origin("herd");
  if (!fetched) GTEST_SKIP() << "CGAL models absent: run scripts/fetch-models.sh";
  Scene models = make_builtin_scene("herd");
  // bunny, dragon, armadillo, elephant, bunny, armadillo.
  EXPECT_EQ(occluder_triangles(models), 2u * 75408u + 19994u + 2u * 52000u + 88928u);
  EXPECT_NE(builtin_scene_origin("herd").find("bunny00.off"), std::string::npos);
  EXPECT_GE(models.bounds().lo.y, 0.0f);
}

TEST(SceneClasses, SameSeedSameScene) {
  EXPECT_EQ(position_hash(make_nest_scene(7)), position_hash(make_nest_scene(7)));
  EXPECT_NE(position_hash(make_nest_scene(7)), position_hash(make_nest_scene(8)));
  EXPECT_EQ(position_hash(make_garden_scene(7)), position_hash(make_garden_scene(7)));
  EXPECT_NE(position_hash(make_garden_scene(7)), position_hash(make_garden_scene(8)));
  EXPECT_EQ(position_hash(make_herd_scene(7, HerdSource::procedural, 96)),
            position_hash(make_herd_scene(7, HerdSource::procedural, 96)));
  EXPECT_NE(position_hash(make_herd_scene(7, HerdSource::procedural, 96)),
            position_hash(make_herd_scene(8, HerdSource::procedural, 96)));
  // The built-in names are the default seed.
  EXPECT_EQ(position_hash(make_builtin_scene("nest")), position_hash(make_nest_scene()));
}

/// gears's and dcs's masks against raytrace's on a small frame of `scene`.
void expect_sample_exact_masks(Scene scene) {
  const test::TestFrame t = test::make_test_frame(std::move(scene), 64, 64, test::grid_samples(4));
  const MethodResult reference = t.run("raytrace", {}, true);
  for (const char* method : {"gears", "dcs"}) {
    SCOPED_TRACE(method);
    test::expect_equal_masks(test::compare_masks(t, reference, t.run(method, {}, true)));
  }
}

// The masks on smaller scenes of the same generators: `dcs` on the built-in sizes takes 6-20 s at
// 64x64 (every twig and leaf edge is a silhouette, thousands of wedges per receiver), too slow for
// a test under the sanitizers; the full sizes are measured in docs/results.md.
TEST(SceneClasses, MasksEqualRaytraceOnNest) {
  expect_sample_exact_masks(make_nest_scene(kSceneClassSeed, 1500));
}

// gears alone on the built-in nest (120 000 twig triangles): every mismatch a numerical tie.
TEST(SceneClasses, GearsMasksEqualRaytraceOnTheFullNest) {
  const test::TestFrame t =
      test::make_test_frame(make_builtin_scene("nest"), 32, 32, test::grid_samples(2));
  test::expect_equal_masks(test::compare_masks(t, "gears"), 50);
}

TEST(SceneClasses, MasksEqualRaytraceOnGarden) {
  expect_sample_exact_masks(make_garden_scene(kSceneClassSeed, 5));
}

TEST(SceneClasses, MasksEqualRaytraceOnHerd) {
  expect_sample_exact_masks(make_herd_scene(kSceneClassSeed, HerdSource::procedural, 48));
}

}  // namespace
}  // namespace penumbra
