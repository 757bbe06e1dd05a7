// A mesh file's own animation: MD2 keyframes as vertex clips (assimp's test models, skipped when
// they are not fetched), their validation, and clips named in a scene file.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <glm/gtc/matrix_transform.hpp>
#include <optional>
#include <string>
#include <tuple>
#include <vector>

#include "penumbra/core/error.hpp"
#include "penumbra/pipeline/sequence.hpp"
#include "penumbra/scene/md2_file.hpp"
#include "penumbra/scene/mesh_clips.hpp"
#include "penumbra/scene/mesh_loader.hpp"
#include "penumbra/scene/model_paths.hpp"
#include "penumbra/scene/scene_file.hpp"
#include "penumbra/scene/scene_writer.hpp"
#include "penumbra/shadows/registry.hpp"
#include "support/error_of.hpp"
#include "support/frame_helpers.hpp"
#include "support/test_support.hpp"

namespace penumbra {
namespace {

namespace fs = std::filesystem;

using test::error_of;

std::optional<fs::path> faerie() {
  return find_model("faerie.md2");
}

#define REQUIRE_FAERIE()                                                    \
  const std::optional<fs::path> md2 = faerie();                             \
  if (!md2)                                                                 \
  GTEST_SKIP() << "faerie.md2 absent: run scripts/fetch-models.sh (assimp " \
                  "test models)"

float max_displacement(const std::vector<Vec3>& a, const std::vector<Vec3>& b) {
  float d = 0.0f;
  for (size_t i = 0; i < a.size(); ++i) d = std::max(d, glm::length(a[i] - b[i]));
  return d;
}

std::string bytes_of(const fs::path& path) {
  return read_mesh_file_bytes(path);
}

TEST(Md2Clips, ListsTheClipsByFrameName) {
  REQUIRE_FAERIE();
  const std::vector<ClipInfo> clips = list_vertex_clips(*md2);
  std::string names;
  int frames = 0;
  for (const ClipInfo& c : clips) {
    names += c.name + ":" + std::to_string(c.frame_count) + " ";
    EXPECT_EQ(c.first_frame, frames);
    frames += c.frame_count;
  }
  EXPECT_EQ(frames, 198);
  EXPECT_EQ(names,
            "stand:40 run:6 attack:8 pain1:4 pain2:4 pain3:4 jump:6 flip:12 salute:11 taunt:17 "
            "wave:11 point:12 crstnd:19 crwalk:6 crattak:9 crpain:4 crdeath:5 death1:6 death2:6 "
            "death3:8 ");
}

TEST(Md2Clips, EveryFrameHasTheRestMeshVertices) {
  REQUIRE_FAERIE();
  const Mesh rest = load_mesh_file(*md2);
  // 654 triangles; 503 distinct (position in every frame, uv) corners of the 1962.
  EXPECT_EQ(rest.triangles.size(), 654u);
  EXPECT_EQ(rest.positions.size(), 503u);
  const Md2Model model = read_md2(*md2, bytes_of(*md2));
  ASSERT_EQ(model.frames.size(), 198u);
  for (const std::vector<Vec3>& f : model.frames) EXPECT_EQ(f.size(), rest.positions.size());
  EXPECT_EQ(model.frames[0], rest.positions);
  // The clips play the same vertices, placed by the source transform.
  const Mat4 lift = glm::translate(Mat4(1.0f), Vec3(0, 2, 0));
  const VertexClip run = load_vertex_clip(*md2, ClipRef{"run", 0, 10.0, 1.0}, lift);
  ASSERT_FALSE(run.positions.empty());
  for (const std::vector<Vec3>& f : run.positions) EXPECT_EQ(f.size(), rest.positions.size());
  EXPECT_EQ(run.times_s.front(), 1.0);
  EXPECT_DOUBLE_EQ(run.times_s[1], 1.1);
  EXPECT_EQ(run.source_fps, 10.0);
  float moved = 0.0f;
  for (size_t k = 1; k < run.positions.size(); ++k)
    moved = std::max(moved, max_displacement(run.positions[0], run.positions[k]));
  // Measured (model units: the faerie is about 60 tall): running moves a vertex by 38.4, standing
  // (clip 0, by index) breathes by 1.45.
  EXPECT_EQ(run.positions.size(), 6u);
  EXPECT_NEAR(moved, 38.40f, 0.01f);
  const VertexClip stand = load_vertex_clip(*md2, ClipRef{"", 0, 10.0, 0.0}, Mat4(1.0f));
  EXPECT_EQ(stand.name, "stand");
  EXPECT_EQ(stand.positions.size(), 40u);
  EXPECT_NEAR(max_displacement(stand.positions[0], stand.positions.back()), 1.4515f, 1e-3f);
  EXPECT_EQ(stand.positions[0], rest.positions);
}

TEST(Md2Clips, MissingClipsAreOneLineErrors) {
  REQUIRE_FAERIE();
  const std::string by_name = error_of([&] {
    load_vertex_clip(*md2, ClipRef{"fly", 0, 10.0, 0.0}, Mat4(1.0f));
  });
  EXPECT_NE(by_name.find("no clip 'fly' ('faerie.md2' has "), std::string::npos) << by_name;
  EXPECT_NE(by_name.find("0 stand, 1 run"), std::string::npos) << by_name;
  EXPECT_EQ(by_name.find('\n'), std::string::npos);
  const std::string by_index = error_of([&] {
    load_vertex_clip(*md2, ClipRef{"", 99, 10.0, 0.0}, Mat4(1.0f));
  });
  EXPECT_NE(by_index.find("no clip 99 ("), std::string::npos) << by_index;
}

/// The faerie with `bytes` patched at `offset`, in a temporary file.
fs::path patched(const fs::path& md2, size_t offset, const std::string& bytes, const char* name) {
  std::string b = bytes_of(md2);
  b.replace(offset, bytes.size(), bytes);
  const fs::path out = fs::temp_directory_path() / name;
  std::ofstream(out, std::ios::binary) << b;
  return out;
}

std::string le32(int32_t v) {
  std::string out(4, '\0');
  for (int i = 0; i < 4; ++i)
    out[i] = static_cast<char>((static_cast<uint32_t>(v) >> (8 * i)) & 0xff);
  return out;
}

TEST(Md2Clips, CorruptFilesAreRefusedBeforeAssimp) {
  REQUIRE_FAERIE();
  const std::vector<std::tuple<size_t, std::string, std::string>> cases = {
      {0, "IDP3", "not an MD2 file (no IDP2 magic)"},
      {4, le32(7), "version 7 (expected 8)"},
      {16, le32(1505), "frame size does not match the vertex count"},
      {40, le32(600), "frame count out of range"},
      {56, le32(320000), "frames lie outside the file"},
      // Triangle 0's first vertex index (the triangles start at 2016).
      {2016, std::string("\xff\x7f", 2), "triangle 0 has a vertex index out of range"},
  };
  for (const auto& [offset, bytes, message] : cases) {
    const fs::path file = patched(*md2, offset, bytes, "penumbra_test_corrupt.md2");
    const std::string e = error_of([&] { load_mesh_file(file); });
    EXPECT_NE(e.find("cannot load mesh"), std::string::npos) << e;
    EXPECT_NE(e.find("MD2: " + message), std::string::npos) << e;
  }
  const std::string short_file = error_of([&] { validate_md2(bytes_of(*md2).substr(0, 60)); });
  EXPECT_EQ(short_file, "MD2: shorter than its header");
}

/// A scene with the faerie playing `clip`.
fs::path faerie_scene(const fs::path& md2, const std::string& clip) {
  const fs::path file = fs::temp_directory_path() / "penumbra_test_faerie" / "faerie.json";
  fs::create_directories(file.parent_path());
  std::ofstream(file) << R"({
  "camera": { "position": [0, 1, 3], "target": [0, 0.5, 0], "width": 32, "height": 32 },
  "materials": [{ "name": "grey" }],
  "meshes": [
    { "name": "floor", "shape": "quad", "center": [0, 0, 0], "edge_u": [0, 0, 4], "edge_v": [4, 0, 0], "material": "grey" },
    { "name": "faerie", "file": ")" +
                             md2.string() + R"(", "material": "grey",
      "transform": { "translate": [0, 0.5, 0], "rotate_deg": [-90, 0, 0], "scale": 0.02 } }
  ],
  "lights": [{ "type": "rect", "center": [0, 3, 0], "edge_u": [1, 0, 0], "edge_v": [0, 0, 1], "radiance": 5 }],
  "animation": { "end": 1, "meshes": [{ "mesh": "faerie", "clip": )" +
                             clip + R"(, "clip_fps": 8 }] }
})";
  return file;
}

TEST(Md2Clips, SceneFilesPlayAClipByNameOrIndex) {
  REQUIRE_FAERIE();
  const Scene s = load_scene_file(faerie_scene(*md2, "\"run\""));
  ASSERT_EQ(s.animation.meshes.size(), 1u);
  const VertexClip& clip = *s.animation.meshes[0].clip;
  EXPECT_EQ(clip.name, "run");
  EXPECT_DOUBLE_EQ(clip.times_s.back(), 5.0 / 8.0);
  const Scene a = pose_scene(s, 0.0), b = pose_scene(s, 0.25);
  // At the start, the clip's first frame (the rest pose is the file's first keyframe, "stand01").
  EXPECT_EQ(a.meshes[1].positions, clip.positions[0]);
  EXPECT_NE(a.meshes[1].positions, s.meshes[1].positions);
  // At scale 0.02, between run frames 0 and 2 (t = 0.25 s at 8 fps): measured 0.4211.
  const float moved = max_displacement(a.meshes[1].positions, b.meshes[1].positions);
  EXPECT_NEAR(moved, 0.4211f, 1e-3f);
  // Written back, the clip is named again (the mesh is a reference to its file).
  const fs::path written = fs::temp_directory_path() / "penumbra_test_faerie_out" / "again.json";
  write_scene_file(s, written);
  const Scene again = load_scene_file(written);
  ASSERT_EQ(again.animation.meshes.size(), 1u);
  EXPECT_EQ(again.animation.meshes[0].clip->name, "run");
  EXPECT_EQ(again.animation.meshes[0].clip->positions, clip.positions);
  EXPECT_EQ(again.animation.meshes[0].clip->times_s, clip.times_s);
  // The same frames as a clip generated in code: written as vertex_keys beside a PLY of the mesh
  // (not the transformed file reference), they load back to the same positions.
  Scene generated = s;
  auto copy = std::make_shared<VertexClip>(clip);
  copy->source_fps = 0.0;
  generated.animation.meshes[0].clip = copy;
  const fs::path written_keys =
      fs::temp_directory_path() / "penumbra_test_faerie_out" / "generated.json";
  write_scene_file(generated, written_keys);
  const Scene keys_again = load_scene_file(written_keys);
  EXPECT_EQ(keys_again.animation.meshes[0].clip->positions, clip.positions);
  EXPECT_EQ(pose_scene(keys_again, 0.3).meshes[1].positions,
            pose_scene(generated, 0.3).meshes[1].positions);
  const Scene by_index = load_scene_file(faerie_scene(*md2, "1"));
  EXPECT_EQ(by_index.animation.meshes[0].clip->positions, clip.positions);
  const std::string e = error_of([&] { load_scene_file(faerie_scene(*md2, "\"fly\"")); });
  EXPECT_NE(e.find("animation.meshes[0].clip: no clip 'fly' ('faerie.md2' has 20 clips: 0 stand, "),
            std::string::npos)
      << e;
}

TEST(GltfMorphClips, AnimatedMorphCubeDeforms) {
  const std::optional<fs::path> gltf = find_model("AnimatedMorphCube.gltf");
  if (!gltf) GTEST_SKIP() << "AnimatedMorphCube.gltf absent: run scripts/fetch-models.sh";
  const std::vector<ClipInfo> clips = list_vertex_clips(*gltf);
  ASSERT_EQ(clips.size(), 1u);
  EXPECT_EQ(clips[0].name, "Square");
  EXPECT_EQ(clips[0].frame_count, 127);
  const Mesh rest = load_mesh_file(*gltf);
  const VertexClip clip = load_vertex_clip(*gltf, ClipRef{"", 0, 10.0, 0.5}, Mat4(1.0f));
  ASSERT_EQ(clip.positions.size(), 127u);
  for (const std::vector<Vec3>& p : clip.positions) EXPECT_EQ(p.size(), rest.positions.size());
  EXPECT_EQ(clip.times_s.front(), 0.5);
  float moved = 0.0f;
  size_t widest = 0;
  for (size_t k = 0; k < clip.positions.size(); ++k) {
    const float d = max_displacement(rest.positions, clip.positions[k]);
    if (d > moved) moved = d, widest = k;
  }
  // Measured: the clip spans the file's 4.2 s, starts at the rest shape, and at its widest (key
  // 102) moves a vertex by 1.989 (the cube is 2 wide once its node's scale is applied).
  EXPECT_NEAR(clip.times_s.back(), 4.7, 1e-5);  // float key times in the file
  EXPECT_EQ(max_displacement(rest.positions, clip.positions[0]), 0.0f);
  EXPECT_EQ(widest, 102u);
  EXPECT_NEAR(moved, 1.989f, 1e-3f);
  const std::string e = error_of([&] {
    load_vertex_clip(*gltf, ClipRef{"Circle", 0, 10.0, 0.0}, Mat4(1.0f));
  });
  EXPECT_NE(e.find("no clip 'Circle' ('AnimatedMorphCube.gltf' has 1 clips: 0 Square)"),
            std::string::npos)
      << e;
}

TEST(GltfSkinClips, SimpleSkinBends) {
  const std::optional<fs::path> gltf = find_model("simple_skin.gltf");
  if (!gltf) GTEST_SKIP() << "simple_skin.gltf absent: run scripts/fetch-models.sh";
  const std::vector<ClipInfo> clips = list_vertex_clips(*gltf);
  ASSERT_EQ(clips.size(), 1u);
  const Mesh rest = load_mesh_file(*gltf);
  const VertexClip clip = load_vertex_clip(*gltf, ClipRef{"", 0, 10.0, 0.0}, Mat4(1.0f));
  float moved = 0.0f;
  size_t widest = 0;
  for (size_t k = 0; k < clip.positions.size(); ++k) {
    ASSERT_EQ(clip.positions[k].size(), rest.positions.size());
    const float d = max_displacement(clip.positions[0], clip.positions[k]);
    if (d > moved) moved = d, widest = k;
  }
  // 12 rotation keys over 5.5 s turn the upper joint by up to 90° about z (key 2): a top corner,
  // 1.118 from the joint, moves by the chord √2 · 1.118 = 1.5811.
  EXPECT_EQ(clips[0].name, "animation0");
  EXPECT_EQ(clip.positions.size(), 12u);
  EXPECT_EQ(rest.positions.size(), 10u);
  EXPECT_NEAR(clip.times_s.back(), 5.5, 1e-6);
  EXPECT_EQ(widest, 2u);
  EXPECT_NEAR(moved, std::sqrt(2.5f), 1e-4f);
  // The skinned pose is the joints' (glTF ignores the skinned mesh's node): this file's inverse
  // bind matrices put it 0.5 along −x of the unskinned rest mesh load_mesh_file reads.
  EXPECT_NEAR(max_displacement(rest.positions, clip.positions[0]), 0.5f, 1e-5f);
}

/// Every method runs on the running faerie (a deforming MD2 clip), frame after frame: visible
/// fractions in [0, 1] on every surface pixel, and the sample-exact methods equal to raytrace.
TEST(Md2Clips, EveryMethodRunsOnTheRunningFaerie) {
  REQUIRE_FAERIE();
  const Scene rest = load_scene_file(faerie_scene(*md2, "\"run\""));
  std::vector<SequenceMethod> all;
  for (const MethodInfo& info : MethodRegistry::builtin().methods())
    all.push_back({&info, resolve_options(info, {})});
  SequenceRenderer renderer(rest, all, test::grid_samples(4), false);
  for (int frame : {0, 2, 4}) {
    const SequenceFrame f = renderer.render(frame);
    ASSERT_EQ(f.results.size(), all.size());
    const MethodResult* raytrace = nullptr;
    for (const MethodResult& r : f.results)
      if (r.method == "raytrace") raytrace = &r;
    ASSERT_NE(raytrace, nullptr);
    for (const MethodResult& r : f.results) {
      SCOPED_TRACE(r.method + " frame " + std::to_string(frame));
      const Image<float>& lit = r.per_light[0].lit;
      size_t shadowed = 0;
      for (float v : lit.pixels()) {
        ASSERT_TRUE(v >= 0.0f && v <= 1.0f) << v;
        shadowed += v < 1.0f;
      }
      EXPECT_GT(shadowed, 10u);  // the faerie shadows the floor (measured: 19 to 40 pixels)
      if (r.method == "gears" || r.method == "dcs") {
        for (size_t i = 0; i < lit.pixels().size(); ++i)
          EXPECT_NEAR(lit.pixels()[i], raytrace->per_light[0].lit.pixels()[i], 1e-6f);
      }
    }
  }
}

}  // namespace
}  // namespace penumbra
