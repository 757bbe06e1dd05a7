// Malformed glTF animation and skin data: a skinned, animated triangle (one joint, a translation
// channel) with one field broken at a time. Index references out of range and accessors that run
// past their buffer are one-line errors; fields a reader may ignore (an unknown target path, a
// node's skin out of range) load, and every clip then read has finite positions. Never a crash:
// the sanitizer build runs the same cases.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "penumbra/core/error.hpp"
#include "penumbra/scene/gltf_morph.hpp"
#include "penumbra/scene/mesh_loader.hpp"

namespace penumbra {
namespace {

using nlohmann::json;

/// The binary buffer (positions, indices, key times, translations, an inverse bind matrix,
/// joints, weights) and the glTF that reads it from `bin` (a file next to the glTF).
struct SkinnedTriangle {
  std::string bytes;
  json gltf;
};

template <class T>
void append(std::string& out, std::initializer_list<T> values) {
  for (T v : values) out.append(reinterpret_cast<const char*>(&v), sizeof v);
}

SkinnedTriangle skinned_triangle(const std::string& bin) {
  SkinnedTriangle t;
  json views = json::array(), accessors = json::array();
  auto view = [&](const std::function<void()>& write, json accessor) {
    const size_t start = t.bytes.size();
    write();
    views.push_back({{"buffer", 0}, {"byteOffset", start}, {"byteLength", t.bytes.size() - start}});
    while (t.bytes.size() % 4) t.bytes.push_back('\0');
    accessor["bufferView"] = views.size() - 1;
    accessors.push_back(accessor);
  };
  view(
      [&] {
        append<float>(t.bytes, {0, 0, 0, 1, 0, 0, 0, 1, 0});
      },
      {{"componentType", 5126},
       {"count", 3},
       {"type", "VEC3"},
       {"min", {0, 0, 0}},
       {"max", {1, 1, 0}}});
  view(
      [&] {
        append<uint16_t>(t.bytes, {0, 1, 2});
      },
      {{"componentType", 5123}, {"count", 3}, {"type", "SCALAR"}});
  view(
      [&] {
        append<float>(t.bytes, {0, 1});
      },
      {{"componentType", 5126}, {"count", 2}, {"type", "SCALAR"}, {"min", {0}}, {"max", {1}}});
  view(
      [&] {
        append<float>(t.bytes, {0, 0, 0, 1, 0, 0});
      },
      {{"componentType", 5126}, {"count", 2}, {"type", "VEC3"}});
  view(
      [&] {
        append<float>(t.bytes, {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1});
      },
      {{"componentType", 5126}, {"count", 1}, {"type", "MAT4"}});
  view(
      [&] {
        append<uint8_t>(t.bytes, {0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0});
      },
      {{"componentType", 5121}, {"count", 3}, {"type", "VEC4"}});
  view(
      [&] {
        append<float>(t.bytes, {1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0});
      },
      {{"componentType", 5126}, {"count", 3}, {"type", "VEC4"}});
  t.gltf = {{"asset", {{"version", "2.0"}}},
            {"scene", 0},
            {"scenes", {{{"nodes", {0, 1}}}}},
            {"nodes", {{{"mesh", 0}, {"skin", 0}}, {{"name", "joint"}}}},
            {"meshes",
             {{{"primitives",
                {{{"attributes", {{"POSITION", 0}, {"JOINTS_0", 5}, {"WEIGHTS_0", 6}}},
                  {"indices", 1}}}}}}},
            {"skins", {{{"joints", {1}}, {"inverseBindMatrices", 4}}}},
            {"animations",
             {{{"channels", {{{"sampler", 0}, {"target", {{"node", 1}, {"path", "translation"}}}}}},
               {"samplers", {{{"input", 2}, {"output", 3}, {"interpolation", "LINEAR"}}}}}}},
            {"buffers", {{{"byteLength", t.bytes.size()}, {"uri", bin}}}},
            {"bufferViews", views},
            {"accessors", accessors}};
  return t;
}

struct Case {
  const char* name;
  std::function<void(json&)> edit;
  bool loads;  // false: a one-line error is expected
};

/// Loads the case's file as a mesh and reads its clips: "" when both work (and the clips'
/// positions are finite), else the Error's message. `frames`: the clips' frames read.
std::string load(const Case& c, const std::filesystem::path& dir, size_t& frames) {
  SkinnedTriangle t = skinned_triangle(std::string(c.name) + ".bin");
  c.edit(t.gltf);
  std::ofstream(dir / (std::string(c.name) + ".bin"), std::ios::binary) << t.bytes;
  const std::filesystem::path path = dir / (std::string(c.name) + ".gltf");
  std::ofstream(path) << t.gltf.dump();
  try {
    const Mesh mesh = load_mesh_file(path);
    for (const MorphClip& clip : read_gltf_morph_clips(path, mesh.positions.size()))
      for (const std::vector<Vec3>& frame : clip.positions) {
        ++frames;
        for (const Vec3& p : frame)
          if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
            return "non-finite clip position";
      }
    return "";
  } catch (const Error& e) {
    return e.what();
  }
}

TEST(GltfAnimationInput, MalformedAnimationAndSkinData) {
  const std::filesystem::path dir = std::filesystem::temp_directory_path() /
                                    ("penumbra_gltf_animation_" + std::to_string(getpid()));
  std::filesystem::create_directories(dir);
  auto channel = [](json& j) -> json& { return j["animations"][0]["channels"][0]; };
  auto sampler = [](json& j) -> json& { return j["animations"][0]["samplers"][0]; };
  const Case cases[] = {
      {"intact", [](json&) {}, true},
      {"channel_node", [&](json& j) { channel(j)["target"]["node"] = 99; }, false},
      {"channel_sampler", [&](json& j) { channel(j)["sampler"] = 5; }, false},
      {"sampler_input", [&](json& j) { sampler(j)["input"] = 50; }, false},
      {"sampler_output", [&](json& j) { sampler(j)["output"] = 50; }, false},
      {"output_too_short", [](json& j) { j["accessors"][3]["count"] = 1; }, false},
      {"input_past_buffer", [](json& j) { j["accessors"][2]["count"] = 2000000000; }, false},
      {"skin_joint", [](json& j) { j["skins"][0]["joints"] = {42}; }, false},
      {"bind_matrices", [](json& j) { j["skins"][0]["inverseBindMatrices"] = 77; }, false},
      {"too_few_bind_matrices",
       [](json& j) {
         j["skins"][0]["joints"] = {1, 1, 1};
       },
       false},
      {"joints_accessor",
       [](json& j) { j["meshes"][0]["primitives"][0]["attributes"]["JOINTS_0"] = 99; }, false},
      {"weights_accessor",
       [](json& j) { j["meshes"][0]["primitives"][0]["attributes"]["WEIGHTS_0"] = 99; }, false},
      {"unknown_path", [&](json& j) { channel(j)["target"]["path"] = "bogus"; }, true},
      {"node_skin", [](json& j) { j["nodes"][0]["skin"] = 9; }, true},
  };
  for (const Case& c : cases) {
    size_t frames = 0;
    const std::string error = load(c, dir, frames);
    SCOPED_TRACE(c.name);
    if (c.loads) {
      EXPECT_EQ(error, "");
      EXPECT_GE(frames, 2u);  // the translation's two keys were read and posed
    } else {
      EXPECT_NE(error, "");
      EXPECT_EQ(error.find('\n'), std::string::npos) << error;    // one line
      EXPECT_NE(error.find(c.name), std::string::npos) << error;  // names the file
    }
  }
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace penumbra
