// JSON scene files (docs/scene-format.md) and mesh files through assimp.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <set>
#include <string>
#include <vector>

#include "penumbra/core/error.hpp"
#include "penumbra/scene/builtin_scenes.hpp"
#include "penumbra/scene/mesh_loader.hpp"
#include "penumbra/scene/model_paths.hpp"
#include "penumbra/scene/scene_file.hpp"
#include "penumbra/scene/topology.hpp"
#include "support/error_of.hpp"
#include "support/test_support.hpp"

namespace penumbra {
namespace {

namespace fs = std::filesystem;

std::string scenes_dir() {
  return test::data_path("scenes");
}

using test::error_of;

void expect_vec3(const Vec3& got, const Vec3& want, float tol = 1e-6f) {
  EXPECT_NEAR(got.x, want.x, tol);
  EXPECT_NEAR(got.y, want.y, tol);
  EXPECT_NEAR(got.z, want.z, tol);
}

const Mesh& mesh_named(const Scene& s, const std::string& name) {
  for (const Mesh& m : s.meshes)
    if (m.name == name) return m;
  throw std::runtime_error("no mesh named " + name);
}

bool has_position(const Mesh& m, const Vec3& p, float tol = 1e-5f) {
  return std::any_of(m.positions.begin(), m.positions.end(),
                     [&](const Vec3& q) { return glm::length(q - p) < tol; });
}

/// Six times the signed volume enclosed by a closed mesh (positive when it faces outward).
double signed_volume6(const Mesh& m) {
  double v = 0.0;
  for (size_t t = 0; t < m.triangle_count(); ++t)
    v += glm::dot(m.vertex(t, 0), glm::cross(m.vertex(t, 1), m.vertex(t, 2)));
  return v;
}

float srgb_to_linear(float c) {
  return c <= 0.04045f ? c / 12.92f : std::pow((c + 0.055f) / 1.055f, 2.4f);
}

TEST(SceneFile, FullExampleLoadsEveryField) {
  const Scene s = load_scene_file(scenes_dir() + "/full.json");
  EXPECT_EQ(s.name, "full");

  expect_vec3(s.camera.position, Vec3(0, 2, 5));
  expect_vec3(s.camera.target, Vec3(0, 0.5f, 0));
  expect_vec3(s.camera.up, Vec3(0, 1, 0));
  EXPECT_FLOAT_EQ(s.camera.vfov_deg, 40.0f);
  EXPECT_EQ(s.camera.width, 320);
  EXPECT_EQ(s.camera.height, 240);
  expect_vec3(s.ambient, Vec3(0.01f, 0.02f, 0.03f));

  // Materials, in file order.
  ASSERT_EQ(s.materials.size(), 4u);
  EXPECT_EQ(s.materials[0].name, "ground");
  expect_vec3(s.materials[1].albedo, Vec3(0.7f, 0.2f, 0.1f));
  EXPECT_TRUE(s.materials[1].is_opaque());
  EXPECT_EQ(s.materials[2].name, "leaves");
  EXPECT_FLOAT_EQ(s.materials[3].transmittance, 0.25f);
  EXPECT_EQ(s.materials[3].alpha_texture, -1);

  // Textures: the alpha mask (alpha channel of an RGBA PNG, /255, v = 0 at the image's bottom
  // row) and the emission map (RGB, sRGB decoded).
  ASSERT_EQ(s.textures.size(), 2u);
  ASSERT_GE(s.materials[2].alpha_texture, 0);
  const Texture& alpha = s.textures[s.materials[2].alpha_texture];
  EXPECT_EQ(alpha.width, 2);
  EXPECT_EQ(alpha.height, 2);
  EXPECT_EQ(alpha.channels, 1);
  EXPECT_FLOAT_EQ(alpha.channel(0, 0, 0), 51.0f / 255.0f);   // bottom-left of the image
  EXPECT_FLOAT_EQ(alpha.channel(1, 0, 0), 102.0f / 255.0f);  // bottom-right
  EXPECT_FLOAT_EQ(alpha.channel(0, 1, 0), 0.0f);             // top-left
  EXPECT_FLOAT_EQ(alpha.channel(1, 1, 0), 1.0f);             // top-right
  ASSERT_GE(s.lights[0].emission_texture, 0);
  const Texture& emission = s.textures[s.lights[0].emission_texture];
  EXPECT_EQ(emission.channels, 3);
  EXPECT_EQ(emission.width, 2);
  EXPECT_EQ(emission.height, 1);
  EXPECT_FLOAT_EQ(emission.channel(0, 0, 0), 1.0f);
  EXPECT_NEAR(emission.channel(0, 0, 1), srgb_to_linear(128.0f / 255.0f), 1e-6f);
  EXPECT_NEAR(emission.channel(0, 0, 1), 0.2158605f, 1e-5f);
  EXPECT_FLOAT_EQ(emission.channel(0, 0, 2), 0.0f);
  expect_vec3(emission.sample_rgb(Vec2(0.75f, 0.5f)), Vec3(0, 0, 1));

  // Meshes.
  ASSERT_EQ(s.meshes.size(), 5u);
  const Mesh& floor = mesh_named(s, "floor");
  EXPECT_EQ(floor.triangle_count(), 2u);
  EXPECT_EQ(floor.material, 0);
  EXPECT_FALSE(floor.casts_shadows);
  EXPECT_TRUE(floor.receives_shadows);
  EXPECT_TRUE(has_position(floor, Vec3(-5, 0, -5)));
  EXPECT_TRUE(has_position(floor, Vec3(5, 0, 5)));

  const Mesh& crate = mesh_named(s, "crate");
  EXPECT_EQ(crate.triangle_count(), 12u);
  EXPECT_EQ(crate.material, 1);
  expect_vec3(crate.bounds().lo, Vec3(-1.5f, 0, -0.5f));
  expect_vec3(crate.bounds().hi, Vec3(-0.5f, 1, 0.5f));
  EXPECT_TRUE(analyze_topology(crate).closed_manifold);

  // The sphere (rings 8, segments 16) scaled by (1, 2, 1) about the origin: an ellipsoid centred
  // at (1, 1, 0) with semi-axes (0.5, 1, 0.5). Its normals went through the inverse transpose,
  // so they are the ellipsoid's gradient direction, not the scaled sphere normals.
  const Mesh& ball = mesh_named(s, "ball");
  EXPECT_EQ(ball.triangle_count(), 16u * (2u * 6u + 2u));
  EXPECT_EQ(ball.material, 3);
  EXPECT_TRUE(ball.casts_shadows);
  EXPECT_FALSE(ball.receives_shadows);
  expect_vec3(ball.bounds().lo, Vec3(0.5f, 0, -0.5f), 1e-5f);
  expect_vec3(ball.bounds().hi, Vec3(1.5f, 2, 0.5f), 1e-5f);
  ASSERT_EQ(ball.normals.size(), ball.positions.size());
  for (size_t i = 0; i < ball.positions.size(); ++i) {
    const Vec3 d = ball.positions[i] - Vec3(1, 1, 0);
    const Vec3 gradient = glm::normalize(Vec3(d.x / 0.25f, d.y / 1.0f, d.z / 0.25f));
    expect_vec3(ball.normals[i], gradient, 1e-4f);
  }
  EXPECT_GT(signed_volume6(ball), 0.0);

  // quad.obj (unit square in xz facing +y): scale (2,1,1), rotate 90° about x, translate y 1.5.
  const Mesh& panel = mesh_named(s, "panel");
  EXPECT_EQ(panel.material, 2);
  EXPECT_EQ(panel.triangle_count(), 2u);
  ASSERT_EQ(panel.uvs.size(), 4u);
  ASSERT_EQ(panel.normals.size(), 4u);
  for (const Vec3& n : panel.normals) expect_vec3(n, Vec3(0, 0, 1), 1e-6f);
  EXPECT_TRUE(has_position(panel, Vec3(1, 1.0f, 0)));   // from (0.5, 0, 0.5)
  EXPECT_TRUE(has_position(panel, Vec3(-1, 2.0f, 0)));  // from (-0.5, 0, -0.5)

  // tetra.off through the row-major matrix: (x, y, z) -> (x + 0.5, 2y, z - 1). Default name: the
  // file's stem.
  const Mesh& tetra = mesh_named(s, "tetra");
  EXPECT_EQ(tetra.triangle_count(), 4u);
  EXPECT_TRUE(has_position(tetra, Vec3(0.5f, 0, -1)));
  EXPECT_TRUE(has_position(tetra, Vec3(0.5f, 2, -1)));
  EXPECT_TRUE(has_position(tetra, Vec3(1.5f, 0, -1)));
  EXPECT_TRUE(has_position(tetra, Vec3(0.5f, 0, 0)));

  // Lights.
  ASSERT_EQ(s.lights.size(), 4u);
  const Light& rect = s.lights[0];
  EXPECT_EQ(rect.name, "key");
  EXPECT_EQ(rect.shape, LightShape::rect);
  expect_vec3(rect.center, Vec3(0, 3, 0));
  expect_vec3(rect.edge_u, Vec3(1, 0, 0));
  expect_vec3(rect.edge_v, Vec3(0, 0, 1));
  expect_vec3(rect.radiance, Vec3(8, 8, 7));
  EXPECT_TRUE(rect.two_sided);
  EXPECT_TRUE(rect.is_textured());
  const Light& disk = s.lights[1];
  EXPECT_EQ(disk.name, "lights[1]");
  EXPECT_EQ(disk.shape, LightShape::disk);
  expect_vec3(disk.normal, Vec3(0, -1, 0));  // normalised
  EXPECT_FLOAT_EQ(disk.radius, 0.25f);
  expect_vec3(disk.radiance, Vec3(4));
  EXPECT_FALSE(disk.two_sided);
  const Light& sphere = s.lights[2];
  EXPECT_EQ(sphere.shape, LightShape::sphere);
  EXPECT_FLOAT_EQ(sphere.radius, 0.2f);
  expect_vec3(sphere.center, Vec3(-2, 3, 0));
  const Light& point = s.lights[3];
  EXPECT_EQ(point.shape, LightShape::point);
  expect_vec3(point.center, Vec3(0, 4, 2));
  expect_vec3(point.radiance, Vec3(1));
  EXPECT_FALSE(point.is_textured());
}

TEST(SceneFile, MinimalSceneUsesDefaults) {
  const Scene s = load_scene_file(scenes_dir() + "/minimal.json");
  const Camera defaults;
  EXPECT_FLOAT_EQ(s.camera.vfov_deg, defaults.vfov_deg);
  EXPECT_EQ(s.camera.width, defaults.width);
  EXPECT_EQ(s.camera.height, defaults.height);
  expect_vec3(s.camera.up, Vec3(0, 1, 0));
  expect_vec3(s.ambient, Scene().ambient);
  ASSERT_EQ(s.materials.size(), 1u);
  expect_vec3(s.materials[0].albedo, Material().albedo);
  EXPECT_FLOAT_EQ(s.materials[0].transmittance, 0.0f);
  EXPECT_TRUE(s.textures.empty());
  ASSERT_EQ(s.meshes.size(), 2u);
  EXPECT_EQ(s.meshes[0].name, "quad");
  EXPECT_EQ(s.meshes[1].name, "box");
  for (const Mesh& m : s.meshes) {
    EXPECT_TRUE(m.casts_shadows);
    EXPECT_TRUE(m.receives_shadows);
  }
  EXPECT_EQ(s.triangle_count(), 14u);
  ASSERT_EQ(s.lights.size(), 2u);
  EXPECT_FALSE(s.lights[0].two_sided);
  EXPECT_EQ(s.lights[0].emission_texture, -1);
}

TEST(SceneFile, MirrorTransformKeepsTrianglesFacingOutward) {
  const Scene s = load_scene_file(scenes_dir() + "/mirrored.json");
  const Mesh& original = mesh_named(s, "original");
  const Mesh& mirrored = mesh_named(s, "mirrored");
  EXPECT_GT(signed_volume6(original), 0.0);
  EXPECT_NEAR(signed_volume6(mirrored), signed_volume6(original), 1e-6);
  EXPECT_TRUE(has_position(mirrored, Vec3(-1, 0, 0)));
  EXPECT_TRUE(analyze_topology(mirrored).closed_manifold);
}

TEST(SceneFile, RelativePathsResolveAgainstTheSceneFolder) {
  const fs::path old_cwd = fs::current_path();
  fs::current_path(fs::temp_directory_path());
  std::string error;
  try {
    const Scene s = load_scene_file(fs::path(scenes_dir()) / "full.json");
    EXPECT_EQ(s.textures.size(), 2u);
  } catch (const Error& e) {
    error = e.what();
  }
  // And a scene given relative to the working directory: base folder "." or "sub/".
  fs::current_path(scenes_dir());
  try {
    EXPECT_EQ(load_scene_file("full.json").meshes.size(), 5u);
    EXPECT_EQ(load_scene_file("broken/../full.json").meshes.size(), 5u);
  } catch (const Error& e) {
    error = e.what();
  }
  fs::current_path(old_cwd);
  EXPECT_EQ(error, "");
}

/// Every file in tests/data/scenes/broken must fail with a message containing these substrings.
const std::map<std::string, std::vector<std::string>>& broken_expectations() {
  static const std::map<std::string, std::vector<std::string>> table = {
      {"syntax_missing_comma.json", {"invalid JSON: parse error at line 2, column"}},
      {"syntax_trailing_comma.json",
       {"invalid JSON: parse error at line", "expected string literal"}},
      {"empty_file.json", {"invalid JSON", "unexpected end of input"}},
      {"number_overflow.json", {"number overflow parsing '1e999' at line 81"}},
      {"duplicate_key.json", {"duplicate key 'radius'"}},
      {"top_level_array.json", {"top level: expected an object (got an array of 0 elements)"}},
      {"unknown_top_key.json", {"unknown key 'light' (did you mean 'lights'?)"}},
      {"unknown_camera_key.json",
       {"camera: unknown key 'fov' (did you mean 'fov_deg'?)", "allowed: position, target"}},
      {"missing_camera.json", {"missing required field 'camera'"}},
      {"missing_camera_target.json", {"camera: missing required field 'target'"}},
      {"camera_position_two_numbers.json",
       {"camera.position: expected an array of 3 numbers (got an array of 2 elements)"}},
      {"camera_up_parallel.json", {"camera.up: is zero or parallel to the view direction"}},
      {"camera_fov_180.json", {"camera.fov_deg: must be in (0, 180) degrees"}},
      {"camera_width_fraction.json", {"camera.width: expected an integer (got the number 512.5)"}},
      {"camera_width_zero.json", {"camera.width: must be in 1..16384"}},
      {"radius_as_string.json", {"lights[1].radius: expected a number (got the string \"0.5\")"}},
      {"nan_as_string.json", {"lights[0].center[1]: expected a number (got the string \"NaN\")"}},
      {"number_too_large_for_float.json", {"lights[1].radius: number out of range"}},
      {"negative_radius.json", {"lights[1].radius: must be positive"}},
      {"zero_area_rect_light.json", {"lights[0]: edge_u and edge_v span zero area"}},
      {"unknown_light_type.json", {"lights[0].type: unknown light type 'spot'"}},
      {"missing_light_type.json", {"lights[0]: missing required field 'type'"}},
      {"missing_radiance.json", {"lights[0]: missing required field 'radiance'"}},
      {"negative_radiance.json", {"lights[0].radiance: must not be negative"}},
      {"light_key_of_other_type.json", {"lights[1]: unknown key 'edge_u'"}},
      {"zero_disk_normal.json", {"lights[1].normal: must be nonzero"}},
      {"empty_lights.json", {"lights: must contain at least one light"}},
      {"lights_not_array.json", {"lights: expected an array of lights (got an object)"}},
      {"light_not_object.json", {"lights[1]: expected an object (got the number 3)"}},
      {"missing_mesh_file.json",
       {"meshes[2].file: cannot load mesh", "does_not_exist.obj': no such file"}},
      {"unknown_material.json", {"meshes[1].material: unknown material 'stone' (defined: grey)"}},
      {"missing_material.json", {"meshes[1]: missing required field 'material'"}},
      {"duplicate_material.json", {"materials[1].name: duplicate material name 'grey'"}},
      {"empty_materials.json", {"materials: must contain at least one material"}},
      {"albedo_above_one.json", {"materials[0].albedo: components must be in [0, 1]"}},
      {"transmittance_one.json", {"materials[0].transmittance: must be in [0, 1)"}},
      {"missing_alpha_texture.json",
       {"materials[0].alpha_texture: cannot load texture", "no_such_texture.png': no such file"}},
      {"alpha_texture_without_uvs.json",
       {"mesh 'box': alpha-textured material needs texture coordinates"}},
      {"file_and_shape.json", {"meshes[1]: give either 'file' or 'shape', not both"}},
      {"neither_file_nor_shape.json", {"meshes[1]: missing required field 'file' or 'shape'"}},
      {"unknown_shape.json", {"meshes[1].shape: unknown shape 'cone'"}},
      {"shape_key_of_other_shape.json", {"meshes[1]: unknown key 'radius'"}},
      {"negative_half_extent.json", {"meshes[1].half_extent: components must be positive"}},
      {"zero_area_quad.json", {"meshes[0]: edge_u and edge_v span zero area"}},
      {"sphere_one_ring.json", {"meshes[2].rings: must be in 2..1024"}},
      {"casts_shadows_string.json",
       {"meshes[1].casts_shadows: expected true or false (got the string \"yes\")"}},
      {"transform_matrix_15_numbers.json",
       {"meshes[1].transform.matrix: expected an array of 16 numbers"}},
      {"transform_matrix_projective.json",
       {"meshes[1].transform.matrix: the last row must be [0, 0, 0, 1]"}},
      {"transform_matrix_singular.json", {"meshes[1].transform: is singular"}},
      {"transform_matrix_and_translate.json",
       {"meshes[1].transform: give either 'matrix' or translate/rotate_deg/scale"}},
      {"transform_zero_scale.json", {"meshes[1].transform.scale: must be nonzero"}},
      {"transform_typo.json",
       {"meshes[1].transform: unknown key 'translation' (did you mean 'translate'?)"}},
      {"transform_rotate_not_array.json",
       {"meshes[1].transform.rotate_deg: expected an array of 3 numbers (got the number 45)"}},
      {"no_triangles.json", {"meshes[0].file: cannot load mesh", "points_only.obj"}},
      // Coordinates that would hand Embree a non-finite or out-of-range ray are refused.
      {"nonfinite_cam_target_1e20.json", {"camera.target[1]: beyond 1e15 in magnitude"}},
      {"nonfinite_cam_3e38.json", {"camera.position[0]: beyond 1e15 in magnitude"}},
      {"nonfinite_cam_down.json", {"camera.up: is zero or parallel to the view direction"}},
      {"nonfinite_big_light_1e19.json", {"light 'lights[0]': extends beyond 1e15 in magnitude"}},
      {"nonfinite_big_light_1e20.json", {"light 'lights[0]': extends beyond 1e15 in magnitude"}},
      {"nonfinite_big_light_3e38.json", {"light 'lights[0]': extends beyond 1e15 in magnitude"}},
      {"nonfinite_ssm_far_mesh.json", {"meshes[2].center[2]: beyond 1e15 in magnitude"}},
      // Control characters from the file are escaped: a "\n" in a key cannot forge a line.
      {"control_char_key.json", {"camera: unknown key 'fov\\nPWNED: fake line'"}},
      {"control_char_material.json", {"unknown material 'x\\ny'"}},
      {"control_char_path.json", {"cannot load mesh", "a\\nb.obj': no such file"}},
  };
  return table;
}

TEST(SceneFile, BrokenFilesThrowErrorsNamingTheProblem) {
  const fs::path dir = fs::path(scenes_dir()) / "broken";
  std::set<std::string> seen;
  for (const auto& entry : fs::directory_iterator(dir)) {
    if (entry.path().extension() != ".json") continue;
    const std::string file = entry.path().filename().string();
    seen.insert(file);
    SCOPED_TRACE(file);
    const auto it = broken_expectations().find(file);
    if (it == broken_expectations().end()) {
      ADD_FAILURE() << "no expected message for broken/" << file << " in the table";
      continue;
    }
    const std::string msg = error_of([&] { load_scene_file(entry.path()); });
    EXPECT_EQ(msg.rfind("scene file '", 0), 0u) << msg;
    EXPECT_NE(msg.find(file), std::string::npos) << "message should name the file: " << msg;
    EXPECT_EQ(msg.find('\n'), std::string::npos) << "message should be one line: " << msg;
    for (const std::string& part : it->second) EXPECT_NE(msg.find(part), std::string::npos) << msg;
  }
  for (const auto& [file, parts] : broken_expectations()) {
    EXPECT_TRUE(seen.count(file)) << "broken/" << file << " is in the table but not on disk";
  }
  EXPECT_GE(seen.size(), 25u);
}

TEST(SceneFile, MissingOrDirectoryPathThrows) {
  EXPECT_NE(error_of([] {
              load_scene_file(scenes_dir() + "/nope.json");
            }).find("nope.json': no such file"),
            std::string::npos);
  EXPECT_NE(error_of([] { load_scene_file(scenes_dir()); }).find("is a directory"),
            std::string::npos);
}

TEST(SceneFile, LoadSceneAcceptsBuiltinNamesAndPaths) {
  const Scene quad = load_scene("quad");
  EXPECT_EQ(quad.name, "quad");
  EXPECT_EQ(quad.triangle_count(), 4u);
  const Scene file = load_scene(scenes_dir() + "/minimal.json");
  EXPECT_EQ(file.name, "minimal");
}

TEST(SceneFile, LoadSceneUnknownNameListsBuiltins) {
  const std::string msg = error_of([] { load_scene("no-such-scene"); });
  EXPECT_NE(msg.find("unknown scene 'no-such-scene'"), std::string::npos) << msg;
  for (const BuiltinSceneInfo& info : builtin_scenes())
    EXPECT_NE(msg.find(info.name), std::string::npos) << msg;
}

TEST(MeshLoader, LoadsSmallObjWithNormalsAndUvs) {
  const Mesh m = load_mesh_file(scenes_dir() + "/quad.obj");
  EXPECT_EQ(m.name, "quad");
  EXPECT_EQ(m.positions.size(), 4u);
  EXPECT_EQ(m.triangle_count(), 2u);
  ASSERT_EQ(m.normals.size(), 4u);
  ASSERT_EQ(m.uvs.size(), 4u);
  for (size_t i = 0; i < 4; ++i) {
    expect_vec3(m.normals[i], Vec3(0, 1, 0));
    // uv = (x + 0.5, z + 0.5) for this file.
    EXPECT_NEAR(m.uvs[i].x, m.positions[i].x + 0.5f, 1e-6f);
    EXPECT_NEAR(m.uvs[i].y, m.positions[i].z + 0.5f, 1e-6f);
  }
  // Faces keep the file's winding: counter-clockwise seen from +y.
  for (size_t t = 0; t < m.triangle_count(); ++t) {
    const Vec3 n = glm::cross(m.vertex(t, 1) - m.vertex(t, 0), m.vertex(t, 2) - m.vertex(t, 0));
    EXPECT_GT(n.y, 0.0f);
  }
  expect_vec3(m.bounds().lo, Vec3(-0.5f, 0, -0.5f));
  expect_vec3(m.bounds().hi, Vec3(0.5f, 0, 0.5f));
}

TEST(MeshLoader, LoadsSmallOffJoiningVertices) {
  const Mesh m = load_mesh_file(scenes_dir() + "/tetra.off");
  EXPECT_EQ(m.positions.size(), 4u);
  EXPECT_EQ(m.triangle_count(), 4u);
  EXPECT_TRUE(m.uvs.empty());
  EXPECT_TRUE(analyze_topology(m).closed_manifold);
  EXPECT_GT(signed_volume6(m), 0.0);
  EXPECT_NEAR(signed_volume6(m), 1.0, 1e-6);  // the unit corner tetrahedron: volume 1/6
}

TEST(MeshLoader, MissingFileThrowsError) {
  const std::string msg = error_of([] { load_mesh_file(scenes_dir() + "/missing.obj"); });
  EXPECT_NE(msg.find("cannot load mesh '"), std::string::npos) << msg;
  EXPECT_NE(msg.find("missing.obj': no such file"), std::string::npos) << msg;
}

TEST(MeshLoader, FileWithoutTrianglesThrowsError) {
  // Only points and lines: SortByPType drops them, leaving nothing to render.
  const std::string msg =
      error_of([] { load_mesh_file(scenes_dir() + "/broken/points_only.obj"); });
  EXPECT_NE(msg.find("cannot load mesh '"), std::string::npos) << msg;
}

TEST(MeshLoader, CorruptHeaderCountsAreRejectedBeforeAllocating) {
  for (const char* file : {"huge_face_count.off", "huge_face_count.ply"}) {
    SCOPED_TRACE(file);
    const std::string msg = error_of([&] { load_mesh_file(scenes_dir() + "/broken/" + file); });
    EXPECT_NE(msg.find("corrupt header: "), std::string::npos) << msg;
    EXPECT_NE(msg.find("bytes can hold"), std::string::npos) << msg;
  }
}

TEST(MeshLoader, UnreadableFormatThrowsError) {
  const std::string msg = error_of([] { load_mesh_file(scenes_dir() + "/minimal.json"); });
  EXPECT_NE(msg.find("cannot load mesh '"), std::string::npos) << msg;
}

// assimp's own collection of broken files (scripts/fetch-models.sh): none may crash; every one
// must be rejected with an Error, except malformed2.obj, whose only faults (an empty face line
// and a missing material) assimp repairs: it loads as an open five-sided box.
TEST(MeshLoader, AssimpInvalidModelsThrowWithoutCrashing) {
  const fs::path dir = models_dir() / "assimp-testmodels" / "invalid";
  std::error_code ec;
  if (!fs::is_directory(dir, ec)) GTEST_SKIP() << dir << " is absent: run scripts/fetch-models.sh";
  size_t files = 0;
  for (const auto& entry : fs::recursive_directory_iterator(dir)) {
    if (!entry.is_regular_file()) continue;
    ++files;
    const std::string name = entry.path().filename().string();
    SCOPED_TRACE(name);
    if (name == "malformed2.obj") {
      try {
        const Mesh m = load_mesh_file(entry.path());
        EXPECT_EQ(m.triangle_count(), 10u);
        EXPECT_EQ(analyze_topology(m).boundary_edges, 4u);
      } catch (const Error&) {
      }
      continue;
    }
    const std::string msg = error_of([&] { load_mesh_file(entry.path()); });
    EXPECT_EQ(msg.rfind("cannot load mesh '", 0), 0u) << msg;
    EXPECT_EQ(msg.find('\n'), std::string::npos) << msg;
  }
  EXPECT_GE(files, 10u);
}

}  // namespace
}  // namespace penumbra
