// The scene file's "animation" object: every field read (tests/data/animation/animated.json),
// written back and read again to the same poses, and a one-line error per kind of mistake.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "penumbra/core/error.hpp"
#include "penumbra/scene/builtin_scenes.hpp"
#include "penumbra/scene/scene_file.hpp"
#include "penumbra/scene/scene_writer.hpp"
#include "support/error_of.hpp"
#include "support/test_support.hpp"

namespace penumbra {
namespace {

namespace fs = std::filesystem;

std::string animated_json() {
  return test::data_path("animation/animated.json");
}

using test::error_of;

fs::path temp_dir(const std::string& name) {
  const fs::path dir = fs::temp_directory_path() / ("penumbra_test_animation_file_" + name);
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

void expect_near(const Vec3& a, const Vec3& b, float tolerance = 1e-5f) {
  EXPECT_NEAR(a.x, b.x, tolerance);
  EXPECT_NEAR(a.y, b.y, tolerance);
  EXPECT_NEAR(a.z, b.z, tolerance);
}

TEST(AnimationFile, ReadsEveryField) {
  const Scene s = load_scene_file(animated_json());
  const Animation& a = s.animation;
  EXPECT_EQ(a.start_s, 0.0);
  EXPECT_EQ(a.end_s, 2.0);
  EXPECT_EQ(a.fps, 24.0);
  EXPECT_EQ(a.frame_count(), 49);
  ASSERT_EQ(a.meshes.size(), 1u);
  EXPECT_EQ(a.meshes[0].mesh, 1);
  EXPECT_EQ(a.meshes[0].transform.pivot, Vec3(-1, 0.5f, 0));
  EXPECT_EQ(a.meshes[0].transform.scale.keys.size(), 3u);
  ASSERT_EQ(a.lights.size(), 3u);
  EXPECT_EQ(a.lights[0].emission_frames.size(), 3u);
  EXPECT_EQ(a.lights[0].emission_fps, 6.0);
  EXPECT_EQ(s.textures.size(), 4u);  // the rest emission texture and three frames
  EXPECT_EQ(a.lights[1].light, 1);
  EXPECT_EQ(a.lights[2].radius.keys[0].time_s, 1.0);
  EXPECT_EQ(a.camera.vfov_deg.keys[1].value, 30.0f);
}

TEST(AnimationFile, PosesTheTracks) {
  const Scene rest = load_scene_file(animated_json());
  const Scene s = pose_scene(rest, 1.0);
  // The crate at t = 1: scaled (1, 2, 1) about its centre, turned 45° about y, lifted 0.5.
  const Vec3 centre(-1, 0.5f, 0);
  const Bounds3 b = s.meshes[1].bounds();
  expect_near(b.center(), centre + Vec3(0, 0.5f, 0));
  EXPECT_NEAR(b.hi.y - b.lo.y, 2.0f, 1e-5f);
  EXPECT_NEAR(b.hi.x - b.lo.x, std::sqrt(2.0f), 1e-5f);  // a unit square turned 45°
  const Light& key = s.lights[0];
  expect_near(key.center, Vec3(0.5f, 3, 0));
  expect_near(key.edge_u, Vec3(1.5f, 0, 0));
  expect_near(key.radiance, Vec3(5.0f));
  EXPECT_NEAR(s.lights[1].radius, 0.375f, 1e-6f);
  EXPECT_NEAR(s.lights[2].radius, 0.2f, 1e-6f);  // held before its first key
  EXPECT_NEAR(s.camera.vfov_deg, 37.5f, 1e-5f);
  // Emission frames at 6 fps: frame floor(6 t) mod 3.
  const std::vector<int>& frames = rest.animation.lights[0].emission_frames;
  EXPECT_EQ(pose_scene(rest, 0.1).lights[0].emission_texture, frames[0]);
  EXPECT_EQ(pose_scene(rest, 0.2).lights[0].emission_texture, frames[1]);
  EXPECT_EQ(pose_scene(rest, 0.4).lights[0].emission_texture, frames[2]);
  EXPECT_EQ(pose_scene(rest, 0.5).lights[0].emission_texture, frames[0]);
}

/// Two scenes pose to the same floats at `times`.
void expect_same_poses(const Scene& a, const Scene& b, const std::vector<double>& times) {
  ASSERT_EQ(a.meshes.size(), b.meshes.size());
  for (double t : times) {
    SCOPED_TRACE("t = " + std::to_string(t));
    const Scene pa = pose_scene(a, t), pb = pose_scene(b, t);
    for (size_t m = 0; m < pa.meshes.size(); ++m)
      EXPECT_EQ(pa.meshes[m].positions, pb.meshes[m].positions);
    for (size_t l = 0; l < pa.lights.size(); ++l) {
      EXPECT_EQ(pa.lights[l].center, pb.lights[l].center);
      EXPECT_EQ(pa.lights[l].edge_u, pb.lights[l].edge_u);
      EXPECT_EQ(pa.lights[l].normal, pb.lights[l].normal);
      EXPECT_EQ(pa.lights[l].radius, pb.lights[l].radius);
      EXPECT_EQ(pa.lights[l].radiance, pb.lights[l].radiance);
      const int ta = pa.lights[l].emission_texture, tb = pb.lights[l].emission_texture;
      ASSERT_EQ(ta < 0, tb < 0);
      if (ta >= 0) {
        EXPECT_EQ(pa.textures[ta].texels, pb.textures[tb].texels);
      }
    }
    EXPECT_EQ(pa.camera.position, pb.camera.position);
    EXPECT_EQ(pa.camera.target, pb.camera.target);
    EXPECT_EQ(pa.camera.vfov_deg, pb.camera.vfov_deg);
  }
}

TEST(AnimationFile, RoundTripsThroughTheWriter) {
  const Scene s = load_scene_file(animated_json());
  const fs::path out = temp_dir("round_trip") / "again.json";
  write_scene_file(s, out);
  const Scene again = load_scene_file(out);
  EXPECT_EQ(again.animation.frame_count(), 49);
  EXPECT_EQ(again.animation.lights[0].emission_frames.size(), 3u);
  expect_same_poses(s, again, {0.0, 0.3, 1.0, 1.7, 2.0});
}

TEST(AnimationFile, BuiltinAnimatedScenesRoundTrip) {
  for (const char* name : {"bunny_orbit", "fence_spin", "flag", "marquee"}) {
    SCOPED_TRACE(name);
    const Scene s = make_builtin_scene(name);
    const fs::path out = temp_dir(name) / (std::string(name) + ".json");
    write_scene_file(s, out);
    const Scene again = load_scene_file(out);
    EXPECT_EQ(again.animation.frame_count(), s.animation.frame_count());
    expect_same_poses(s, again, {0.0, 0.5, 1.25, 2.0});
  }
}

TEST(AnimationFile, WriterNamesSharedNamesApart) {
  // The animation refers to meshes and lights by name: two meshes named alike are written as
  // "fence" and "fence_2", and the spinning one is still the one that spins.
  Scene s = make_builtin_scene("fence_spin");
  s.meshes[0].name = "fence";
  s.lights.push_back(s.lights[0]);
  s.lights[1].center.y += 1.0f;
  LightAnimation l;
  l.light = 1;
  l.radiance.keys = {{0.0, Vec3(1.0f)}, {3.0, Vec3(2.0f)}};
  s.animation.lights.push_back(l);
  const fs::path out = temp_dir("names") / "names.json";
  write_scene_file(s, out);
  const Scene again = load_scene_file(out);
  EXPECT_EQ(again.meshes[0].name, "fence");
  EXPECT_EQ(again.meshes[1].name, "fence_2");
  EXPECT_EQ(again.lights[1].name, "light_2");
  EXPECT_EQ(again.animation.meshes[0].mesh, 1);
  EXPECT_EQ(again.animation.lights[0].light, 1);
  expect_same_poses(s, again, {0.0, 1.0, 2.5});
}

/// A small scene with `animation` as its animation object, loaded from a temporary file.
Scene load_with_animation(const std::string& animation) {
  const fs::path file = temp_dir("errors") / "a.json";
  std::ofstream(file) << R"({
  "camera": { "position": [0, 2, 4], "target": [0, 0, 0] },
  "materials": [{ "name": "grey" }],
  "meshes": [
    { "name": "floor", "shape": "quad", "center": [0, 0, 0], "edge_u": [0, 0, 4], "edge_v": [4, 0, 0], "material": "grey" },
    { "name": "crate", "shape": "box", "center": [0, 0.5, 0], "half_extent": [0.25, 0.25, 0.25], "material": "grey" },
    { "name": "tetra", "file": ")" +
                             test::data_path("scenes/tetra.off") + R"(", "material": "grey" }
  ],
  "lights": [
    { "name": "key", "type": "rect", "center": [0, 3, 0], "edge_u": [1, 0, 0], "edge_v": [0, 0, 1], "radiance": 5 },
    { "name": "disk", "type": "disk", "center": [0, 3, 1], "normal": [0, -1, 0], "radius": 0.2, "radiance": 5 }
  ],
  "animation": )" + animation +
                             "\n}\n";
  return load_scene_file(file);
}

TEST(AnimationFile, BadInputGetsOneLineErrors) {
  const std::vector<std::pair<std::string, std::string>> cases = {
      {R"({"end": 1, "meshes": [{"mesh": "crate", "translate": [[1, [0, 0, 0]], [0.5, [0, 1, 0]]]}]})",
       "animation.meshes[0].translate[1][0]: key time 0.5 is not after the previous key's (1)"},
      {R"({"end": 1, "meshes": [{"mesh": "crate", "translate": [[0, [0, "NaN", 0]]]}]})",
       "animation.meshes[0].translate[0][1][1]: expected a number (got the string \"NaN\")"},
      {R"({"end": 1, "meshes": [{"mesh": "crat", "translate": [[0, [0, 0, 0]]]}]})",
       "animation.meshes[0].mesh: unknown mesh 'crat' (did you mean 'crate'?) (meshes: floor, "
       "crate, tetra)"},
      {R"({"end": 1, "meshes": [{"mesh": "tetra", "clip": "run"}]})",
       "animation.meshes[0].clip: mesh 'tetra.off' has no vertex animation (clips are read from "
       "MD2 and glTF files)"},
      {R"({"end": 1, "meshes": [{"mesh": "crate", "clip": 0}]})",
       "animation.meshes[0].clip: mesh 'crate' is not read from a file"},
      {R"({"end": 1, "fps": 0})", "animation.fps: must be in (0, 1000]"},
      {R"({"end": 1, "fps": -24})", "animation.fps: must be in (0, 1000]"},
      {R"({"start": 2, "end": 1})", "animation.end: is before start (2)"},
      {R"({"start": 0})", "animation: missing required field 'end'"},
      {R"({"end": 1, "meshes": [{"mesh": "crate", "translate": [[0, [0, 1]]]}]})",
       "animation.meshes[0].translate[0][1]: expected an array of 3 numbers (got an array of 2 "
       "elements)"},
      {R"({"end": 1, "meshes": [{"mesh": "crate", "translate": [[0, [0, 0, 0], 1]]}]})",
       "animation.meshes[0].translate[0]: expected a key [time, value] (got an array of 3 "
       "elements)"},
      {R"({"end": 1, "meshes": [{"mesh": "crate", "rotate": [[0, [0, 0, 0]]]}]})",
       "unknown key 'rotate' (did you mean 'rotate_deg'?)"},
      {R"({"end": 1, "meshes": [{"mesh": "crate"}]})",
       "animation.meshes[0]: animates nothing (give translate, rotate_deg, scale, clip or "
       "vertex_keys)"},
      {R"({"end": 1, "meshes": [{"mesh": "crate", "scale": [[0, 0]]}]})",
       "animation.meshes[0].scale[0][1]: must be nonzero"},
      {R"({"end": 1, "lights": [{"light": "disk", "edge_u": [[0, [1, 0, 0]]]}]})",
       "animation.lights[0].edge_u: only a rect light has it (light 'disk' is a disk)"},
      {R"({"end": 1, "lights": [{"light": "key", "emission_frames": ["a.png"]}]})",
       "animation.lights[0]: 'emission_frames' and 'emission_fps' go together"},
      {R"({"end": 1, "lights": [{"light": "key", "emission_fps": 4, "emission_frames": {"pattern": "f%s.png", "count": 2}}]})",
       "animation.lights[0].emission_frames.pattern: needs one %d or %0Nd"},
      {R"({"end": 1, "lights": [{"light": "key", "emission_fps": 4, "emission_frames": {"pattern": "f%d.png", "count": 2}}]})",
       "animation.lights[0].emission_frames.pattern: cannot load texture"},
      {R"({"end": 1, "lights": [{"light": "lamp", "radiance": [[0, 1]]}]})",
       "animation.lights[0].light: unknown light 'lamp'"},
      {R"({"end": 1, "camera": {"fov_deg": [[0, 190]]}})",
       "animation.camera.fov_deg[0][1]: must be in (0, 180) degrees"},
      {R"({"end": 1, "camera": {"position": []}})",
       "animation.camera.position: must contain at least one key"},
  };
  for (const auto& [animation, message] : cases) {
    SCOPED_TRACE(animation);
    const std::string e = error_of([&] { load_with_animation(animation); });
    EXPECT_NE(e.find(message), std::string::npos) << e;
    EXPECT_EQ(e.find('\n'), std::string::npos) << e;
    EXPECT_EQ(e.rfind("scene file ", 0), 0u) << e;
  }
}

}  // namespace
}  // namespace penumbra
