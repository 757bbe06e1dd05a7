// Built-in scenes: the procedural ones always build; the model ones need scripts/fetch-models.sh.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <map>
#include <optional>
#include <set>
#include <string>

#include "penumbra/core/error.hpp"
#include "penumbra/scene/builtin_scenes.hpp"
#include "penumbra/scene/model_paths.hpp"
#include "penumbra/scene/scene_classes.hpp"
#include "penumbra/scene/topology.hpp"

namespace penumbra {
namespace {

/// Sets an environment variable for one scope, restoring the old value afterwards.
class ScopedEnv {
 public:
  ScopedEnv(const char* name, const std::string& value) : name_(name) {
    if (const char* old = std::getenv(name)) old_ = old;
    setenv(name, value.c_str(), 1);
  }
  ~ScopedEnv() {
    if (old_) {
      setenv(name_, old_->c_str(), 1);
    } else {
      unsetenv(name_);
    }
  }

 private:
  const char* name_;
  std::optional<std::string> old_;
};

TEST(BuiltinScenes, NamesAreUniqueAndKnown) {
  std::set<std::string> names;
  for (const BuiltinSceneInfo& info : builtin_scenes()) {
    EXPECT_TRUE(names.insert(info.name).second) << info.name;
    EXPECT_TRUE(is_builtin_scene(info.name));
    EXPECT_FALSE(info.description.empty());
  }
  for (const char* name :
       {"quad", "spheres", "fence", "default", "nest", "garden", "herd", "bunny", "dragon"})
    EXPECT_TRUE(names.count(name)) << name;
  EXPECT_FALSE(is_builtin_scene("nonexistent"));
}

TEST(BuiltinScenes, ProceduralScenesBuildAndValidate) {
  // Triangle counts: ground quad 2; a make_sphere(rings r, segments s) has s * (2 (r - 2) + 2).
  const std::map<std::string, size_t> expected_triangles = {
      {"quad", 2 + 2},
      {"spheres", 2 + 27 * (24 * (2 * 10 + 2))},
      {"fence", 2 + 2},
      {"default", 2 + 12 + 32 * (2 * 14 + 2) + 2},
      {"nest", 2 + 20000 * 6},                                  // twigs of 6 triangles
      {"garden", 2 + 400 * 6 + 400 * 256 * 2},                  // stems of 6, leaf cards of 2
      {"herd", 2 + (herd_models_fetched() ? 363738 : 344160)},  // models or stand-ins
      // The animated scenes' rest poses: the bunny or a make_sphere(64, 128) stand-in; the fence;
      // ground, pole box and a 48 × 32 cloth; ground, three boxes and a make_sphere(16, 32).
      {"bunny_orbit",
       find_model("bunny00.off") ? make_builtin_scene("bunny").triangle_count() : 2 + 128 * 126},
      {"fence_spin", 2 + 2},
      {"flag", 2 + 12 + 2 * 48 * 32},
      {"marquee", 2 + 3 * 12 + 32 * (2 * 14 + 2)},
  };
  size_t built = 0;
  for (const BuiltinSceneInfo& info : builtin_scenes()) {
    if (info.needs_models) continue;
    SCOPED_TRACE(info.name);
    Scene s = make_builtin_scene(info.name);
    ++built;
    EXPECT_EQ(s.name, info.name);
    EXPECT_EQ(validate_scene(s), 0u) << "no degenerate triangles expected";
    EXPECT_FALSE(s.lights.empty());
    ASSERT_TRUE(expected_triangles.count(info.name)) << "add the new scene's triangle count";
    EXPECT_EQ(s.triangle_count(), expected_triangles.at(info.name));
    // Everything sits above the ground plane at y = 0.
    EXPECT_GE(s.bounds().lo.y, 0.0f);
    for (const Light& l : s.lights) EXPECT_GT(l.center.y, s.bounds().lo.y);
  }
  EXPECT_EQ(built, expected_triangles.size());
}

TEST(BuiltinScenes, ProceduralOccludersAreClosedOrOpenAsDesigned) {
  const Scene s = make_builtin_scene("default");
  for (const Mesh& m : s.meshes) {
    SCOPED_TRACE(m.name);
    const MeshTopology t = analyze_topology(m);
    if (m.name == "box" || m.name == "sphere") {
      EXPECT_TRUE(t.closed_manifold);
    } else {
      EXPECT_EQ(t.boundary_edges, 4u);  // the ground and the fence panel are quads
    }
  }
}

TEST(BuiltinScenes, UnknownNameListsTheKnownOnes) {
  try {
    make_builtin_scene("nonexistent");
    FAIL() << "expected penumbra::Error";
  } catch (const Error& e) {
    const std::string msg = e.what();
    for (const BuiltinSceneInfo& info : builtin_scenes())
      EXPECT_NE(msg.find(info.name), std::string::npos);
  }
}

/// The benchmark layout, checked when the model is present.
void check_model_scene(const Scene& s, const std::string& name, size_t min_triangles) {
  ASSERT_EQ(s.meshes.size(), 2u);
  const Mesh& model = s.meshes[1];
  EXPECT_EQ(model.name, name);
  EXPECT_GE(model.triangle_count(), min_triangles);
  const Bounds3 b = model.bounds();
  EXPECT_NEAR(b.diagonal(), 1.0f, 1e-4f);
  EXPECT_NEAR(b.lo.y, 0.0f, 1e-6f);
  EXPECT_NEAR(b.center().x, 0.0f, 1e-5f);
  EXPECT_NEAR(b.center().z, 0.0f, 1e-5f);
  EXPECT_FLOAT_EQ(s.camera.position.x, 1.5f);
  EXPECT_FLOAT_EQ(s.camera.position.y, 1.2f);
  EXPECT_FLOAT_EQ(s.camera.position.z, 1.5f);
  EXPECT_NEAR(glm::length(s.camera.target - b.center()), 0.0f, 1e-5f);
  EXPECT_FLOAT_EQ(s.camera.vfov_deg, 45.0f);
  ASSERT_EQ(s.lights.size(), 1u);
  const Light& l = s.lights[0];
  EXPECT_EQ(l.shape, LightShape::rect);
  EXPECT_NEAR(glm::length(l.edge_u), 0.5f, 1e-6f);
  EXPECT_NEAR(glm::length(l.edge_v), 0.5f, 1e-6f);
  EXPECT_NEAR(glm::length(l.center - (b.center() + Vec3(0, 2, 0))), 0.0f, 1e-5f);
  EXPECT_LT(glm::cross(l.edge_u, l.edge_v).y, 0.0f);  // faces down onto the model
}

TEST(BuiltinScenes, ModelScenesLoadOrExplainHowToFetch) {
  const std::map<std::string, size_t> min_triangles = {{"bunny", 70000}, {"dragon", 19000}};
  for (const auto& [name, triangles] : min_triangles) {
    SCOPED_TRACE(name);
    ASSERT_TRUE(is_builtin_scene(name));
    std::optional<Scene> s;
    try {
      s = make_builtin_scene(name);
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find("fetch-models.sh"), std::string::npos) << e.what();
      continue;
    }
    check_model_scene(*s, name, triangles);
  }
}

TEST(BuiltinScenes, MissingModelsErrorMentionsFetchScript) {
  const std::filesystem::path empty = std::filesystem::temp_directory_path() / "penumbra-no-models";
  std::filesystem::create_directories(empty);
  const ScopedEnv env("PENUMBRA_MODELS", empty.string());
  for (const char* name : {"bunny", "dragon"}) {
    try {
      make_builtin_scene(name);
      ADD_FAILURE() << name << " built without its model";
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find("scripts/fetch-models.sh"), std::string::npos)
          << e.what();
    }
  }
}

TEST(BuiltinScenes, FetchedBunnyHasAbout72kTriangles) {
  if (!find_model("bunny00.off")) GTEST_SKIP() << "bunny00.off absent: run scripts/fetch-models.sh";
  Scene s = make_builtin_scene("bunny");
  const size_t n = s.meshes[1].triangle_count();
  EXPECT_GT(n, 70000u);
  EXPECT_LT(n, 80000u);
}

}  // namespace
}  // namespace penumbra
