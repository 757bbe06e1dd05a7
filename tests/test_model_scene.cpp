// Any model file as a scene: framed like the built-in `bunny` (on the ground, in view, casting a
// visible shadow), Y-up and Z-up both upright; and any scene written as a JSON scene file loads
// back into the same render.
#include <gtest/gtest.h>

#include <cstring>
#include <filesystem>
#include <fstream>

#include "penumbra/core/error.hpp"
#include "penumbra/pipeline/frame.hpp"
#include "penumbra/pipeline/shading.hpp"
#include "penumbra/scene/model_paths.hpp"
#include "penumbra/scene/model_scene.hpp"
#include "penumbra/scene/scene_file.hpp"
#include "penumbra/scene/scene_writer.hpp"

namespace penumbra {
namespace {

namespace fs = std::filesystem;

fs::path temp_dir(const std::string& name) {
  const fs::path d = fs::temp_directory_path() / ("penumbra_test_" + name);
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

/// Writes an OBJ of axis-aligned boxes (lo, hi), faces outward.
void write_boxes_obj(const fs::path& path, const std::vector<std::pair<Vec3, Vec3>>& boxes) {
  std::ofstream f(path);
  int base = 1;
  for (const auto& [lo, hi] : boxes) {
    for (int i = 0; i < 8; ++i)
      f << "v " << (i & 1 ? hi.x : lo.x) << " " << (i & 2 ? hi.y : lo.y) << " "
        << (i & 4 ? hi.z : lo.z) << "\n";
    // Quads by corner bits, counter-clockwise seen from outside.
    const int quads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4},
                             {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
    for (const auto& q : quads)
      f << "f " << base + q[0] << " " << base + q[1] << " " << base + q[2] << " " << base + q[3]
        << "\n";
    base += 8;
  }
}

/// A lamp standing along +z: wide thin base, thin pole, a wider shade on top whose shadow
/// reaches the ground around the base.
fs::path write_z_up_lamp(const fs::path& dir) {
  const fs::path p = dir / "lamp_z_up.obj";
  write_boxes_obj(p, {{Vec3(-0.5f, -0.5f, 0.0f), Vec3(0.5f, 0.5f, 0.05f)},
                      {Vec3(-0.05f, -0.05f, 0.05f), Vec3(0.05f, 0.05f, 1.2f)},
                      {Vec3(-0.7f, -0.7f, 1.2f), Vec3(0.7f, 0.7f, 1.3f)}});
  return p;
}

struct Coverage {
  double model = 0.0;            // fraction of the image's pixels on the model
  double shadowed_ground = 0.0;  // fraction of the ground pixels with V < 0.5
};

Coverage render_coverage(Scene scene) {
  scene.camera.width = scene.camera.height = 96;
  LightSampleSpec spec;
  spec.k = 4;
  const Frame frame(scene, spec);
  const MethodInfo& exact = MethodRegistry::builtin().get("exact");
  const MethodResult r = frame.run(exact, resolve_options(exact, {}), false);
  const GBuffer& g = frame.gbuffer();
  size_t model = 0, ground = 0, shadowed = 0;
  for (size_t i = 0; i < r.per_light[0].lit.size(); ++i) {
    if (g.is_background(i)) continue;
    if (g.mesh_id[i] == 1) ++model;
    if (g.mesh_id[i] == 0) {
      ++ground;
      if (r.per_light[0].lit[i] < 0.5f) ++shadowed;
    }
  }
  Coverage c;
  c.model = static_cast<double>(model) / (96.0 * 96.0);
  c.shadowed_ground = ground ? static_cast<double>(shadowed) / ground : 0.0;
  return c;
}

void expect_framed_upright(const Scene& s, float tall_fraction) {
  ASSERT_EQ(s.meshes.size(), 2u);
  const Bounds3 b = s.meshes[1].bounds();
  EXPECT_NEAR(b.lo.y, 0.0f, 1e-6f);                                // on the ground
  EXPECT_NEAR(b.diagonal(), 1.0f, 1e-5f);                          // scaled to diagonal 1
  EXPECT_NEAR(b.center().x, 0.0f, 1e-6f);                          // centred
  EXPECT_NEAR(b.extent().y / b.diagonal(), tall_fraction, 1e-3f);  // upright
  EXPECT_NEAR(s.lights[0].center.y, b.center().y + 2.0f, 1e-5f);
}

TEST(ModelScene, AGeneratedZUpObjStandsUprightCoversTheViewAndCastsAShadow) {
  const fs::path obj = write_z_up_lamp(temp_dir("lamp"));
  // The lamp is 1.4 × 1.4 × 1.3: its height is 1.3 / sqrt(1.96 + 1.96 + 1.69) of the diagonal.
  const float tall = 1.3f / std::sqrt(5.61f);
  const Scene automatic = load_scene(obj.string());
  expect_framed_upright(automatic, tall);
  const Scene z = load_scene(obj.string(), ModelFraming{0.5f, 2.0f, ModelUp::z, true});
  EXPECT_EQ(std::memcmp(z.meshes[1].positions.data(), automatic.meshes[1].positions.data(),
                        z.meshes[1].positions.size() * sizeof(Vec3)),
            0);
  // Forced y: the lamp lies on its side (its y extent is the shade's 1.4).
  const Scene y = load_scene(obj.string(), ModelFraming{0.5f, 2.0f, ModelUp::y, true});
  EXPECT_NEAR(y.meshes[1].bounds().extent().y, 1.4f / std::sqrt(5.61f), 1e-4f);

  const Coverage c = render_coverage(automatic);
  EXPECT_GE(c.model, 0.10) << c.model;
  EXPECT_GE(c.shadowed_ground, 0.02) << c.shadowed_ground;
}

TEST(ModelScene, LightSizeAndHeightOptionsMoveTheLight) {
  const fs::path obj = write_z_up_lamp(temp_dir("lamp_light"));
  const Scene s = load_scene(obj.string(), ModelFraming{0.25f, 3.0f, ModelUp::automatic, true});
  EXPECT_NEAR(glm::length(s.lights[0].edge_u), 0.25f, 1e-6f);
  EXPECT_NEAR(s.lights[0].center.y - s.meshes[1].bounds().center().y, 3.0f, 1e-5f);
  EXPECT_THROW(load_scene(obj.string(), ModelFraming{0.0f, 2.0f, ModelUp::y, true}), Error);
}

TEST(ModelScene, AFetchedModelIsFramedInViewWithAVisibleShadow) {
  for (const char* name :
       {"bunny00.off", "assimp-testmodels/OBJ/WusonOBJ.obj", "assimp-testmodels/STL/Wuson.stl"}) {
    const fs::path path = models_dir() / name;
    if (!fs::exists(path)) {
      GTEST_SKIP() << path << " absent: run scripts/fetch-models.sh";
    }
    const Scene s = load_scene(path.string());
    EXPECT_NEAR(s.meshes[1].bounds().lo.y, 0.0f, 1e-6f) << name;
    const Coverage c = render_coverage(s);
    EXPECT_GE(c.model, 0.10) << name << " " << c.model;
    EXPECT_GE(c.shadowed_ground, 0.03) << name << " " << c.shadowed_ground;
    std::printf("%s: %.3f of the image on the model, %.3f of the ground shadowed\n", name, c.model,
                c.shadowed_ground);
  }
}

/// Renders `exact` and `raytrace` and the beauty image of both scenes at 48².
void expect_same_render(Scene a, Scene b) {
  for (Scene* s : {&a, &b}) s->camera.width = s->camera.height = 48;
  LightSampleSpec spec;
  spec.k = 4;
  const Frame fa(a, spec), fb(b, spec);
  for (const char* name : {"exact", "raytrace"}) {
    const MethodInfo& m = MethodRegistry::builtin().get(name);
    const MethodResult ra = fa.run(m, resolve_options(m, {}), false);
    const MethodResult rb = fb.run(m, resolve_options(m, {}), false);
    ASSERT_EQ(ra.per_light.size(), rb.per_light.size());
    for (size_t l = 0; l < ra.per_light.size(); ++l)
      EXPECT_EQ(ra.per_light[l].lit.pixels(), rb.per_light[l].lit.pixels()) << a.name << name;
    const Image<Vec3> ia = shade(fa, {&ra.per_light[0]}, ShadingMode::modulate);
    const Image<Vec3> ib = shade(fb, {&rb.per_light[0]}, ShadingMode::modulate);
    float worst = 0.0f;
    for (size_t i = 0; i < ia.size(); ++i) worst = std::max(worst, glm::length(ia[i] - ib[i]));
    EXPECT_LE(worst, 1e-5f) << a.name << " " << name;  // normals renormalised on load
  }
}

TEST(SceneWriter, EveryBuiltinSceneRoundTripsToTheSameRender) {
  const fs::path dir = temp_dir("scene_writer");
  for (const char* name : {"quad", "spheres", "fence", "default"}) {
    const Scene original = load_scene(name);
    const fs::path json = dir / (std::string(name) + ".json");
    write_scene_file(original, json);
    const Scene again = load_scene_file(json);
    EXPECT_EQ(again.name, original.name);
    ASSERT_EQ(again.meshes.size(), original.meshes.size()) << name;
    for (size_t m = 0; m < again.meshes.size(); ++m) {
      EXPECT_EQ(again.meshes[m].triangles.size(), original.meshes[m].triangles.size());
      EXPECT_EQ(again.meshes[m].casts_shadows, original.meshes[m].casts_shadows);
    }
    expect_same_render(original, again);
  }
}

TEST(SceneWriter, AFramedModelIsWrittenAsAReferenceToItsFile) {
  const fs::path dir = temp_dir("scene_writer_model");
  const fs::path obj = write_z_up_lamp(dir);
  const Scene framed = load_scene(obj.string());
  const fs::path json = dir / "lamp.json";
  write_scene_file(framed, json);
  std::ifstream f(json);
  const std::string text((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
  EXPECT_NE(text.find("lamp_z_up.obj"), std::string::npos);
  EXPECT_NE(text.find("\"matrix\""), std::string::npos);
  EXPECT_FALSE(fs::exists(dir / "lamp_meshes" / "1_lamp_z_up.ply"));
  const Scene again = load_scene_file(json);
  expect_same_render(framed, again);
}

}  // namespace
}  // namespace penumbra
