// Tests for the frame's shared stages run beside others or fused (pipeline/frame.hpp): the
// G-buffer traced into layers allocated beforehand, the unshadowed irradiance computed on a
// background thread while a method runs, and the beauty PNG shaded a row at a time must give the
// images computed the plain way, bit for bit.
#include <gtest/gtest.h>

#include <chrono>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <thread>

#include "penumbra/io/image_io.hpp"
#include "penumbra/pipeline/frame.hpp"
#include "penumbra/pipeline/shading.hpp"
#include "penumbra/scene/builtin_scenes.hpp"

namespace penumbra {
namespace {

template <typename T>
bool same_bytes(const Image<T>& a, const Image<T>& b) {
  return a.width() == b.width() && a.height() == b.height() &&
         std::memcmp(a.data(), b.data(), a.size() * sizeof(T)) == 0;
}

void expect_same_gbuffer(const GBuffer& a, const GBuffer& b) {
  EXPECT_TRUE(same_bytes(a.world_pos, b.world_pos));
  EXPECT_TRUE(same_bytes(a.geo_normal, b.geo_normal));
  EXPECT_TRUE(same_bytes(a.shading_normal, b.shading_normal));
  EXPECT_TRUE(same_bytes(a.depth, b.depth));
  EXPECT_TRUE(same_bytes(a.mesh_id, b.mesh_id));
  EXPECT_TRUE(same_bytes(a.prim_id, b.prim_id));
  EXPECT_TRUE(same_bytes(a.uv, b.uv));
  EXPECT_TRUE(same_bytes(a.ray_offset, b.ray_offset));
}

/// The spheres scene at 96×72 with a second, smaller light beside the first: two lights, so the
/// background thread moves from one light's rows to the next.
Scene two_light_scene() {
  Scene scene = make_builtin_scene("spheres");
  scene.camera.width = 96;
  scene.camera.height = 72;
  Light second = scene.lights.front();
  second.center += Vec3(0.7f, 0.2f, -0.4f);
  second.edge_u *= 0.5f;
  second.radiance *= 2.0f;
  scene.lights.push_back(second);
  return scene;
}

TEST(Frame, GBufferIntoAllocatedLayersIsTheTracedOne) {
  const Scene scene = two_light_scene();
  const EmbreeScene embree(scene);
  const GBuffer plain = render_gbuffer(embree, scene.camera);
  size_t background = 0;
  for (size_t i = 0; i < plain.pixel_count(); ++i) background += plain.is_background(i);
  ASSERT_GT(background, 0u);  // the background values must come from background_gbuffer
  ASSERT_LT(background, plain.pixel_count());
  expect_same_gbuffer(plain,
                      render_gbuffer(embree, scene.camera,
                                     background_gbuffer(scene.camera.width, scene.camera.height)));
  // Layers of another size are not used: a new G-buffer of the camera's size is traced.
  const GBuffer other = render_gbuffer(embree, scene.camera, background_gbuffer(17, 5));
  EXPECT_EQ(other.width, scene.camera.width);
  expect_same_gbuffer(plain, other);
  // A Frame given the layers to fill, as `render` gives those it allocated beside the load.
  LightSampleSpec spec;
  spec.k = 2;
  int asked = 0;
  const Frame frame(scene, spec, [&] {
    ++asked;
    return background_gbuffer(scene.camera.width, scene.camera.height);
  });
  EXPECT_EQ(asked, 1);
  expect_same_gbuffer(plain, frame.gbuffer());
}

TEST(Frame, UnshadowedBesideAMethodIsTheAllCoresOne) {
  const Scene scene = two_light_scene();
  LightSampleSpec spec;
  spec.k = 2;
  const Frame plain(scene, spec);
  const int rows = 2 * scene.camera.height;

  // All rows on the background thread: waited for until it has taken every one.
  {
    const Frame frame(scene, spec);
    frame.start_unshadowed_in_background();
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(30);
    while (frame.irradiance_background_rows() < rows && std::chrono::steady_clock::now() < deadline)
      std::this_thread::sleep_for(std::chrono::milliseconds(1));
    ASSERT_EQ(frame.irradiance_background_rows(), rows);
    for (size_t l = 0; l < scene.lights.size(); ++l)
      EXPECT_TRUE(same_bytes(frame.unshadowed(l), plain.unshadowed(l))) << "light " << l;
    EXPECT_GT(frame.irradiance_background_ms(), 0.0);
  }
  // Shared with a method and then all cores, as `render` runs it: whatever the split, the same.
  {
    const Frame frame(scene, spec);
    frame.start_unshadowed_in_background();
    const MethodInfo& info = MethodRegistry::builtin().get("shadow_map");
    frame.run(info, resolve_options(info, {}), false);
    for (size_t l = 0; l < scene.lights.size(); ++l)
      EXPECT_TRUE(same_bytes(frame.unshadowed(l), plain.unshadowed(l))) << "light " << l;
    EXPECT_LE(frame.irradiance_background_rows(), rows);
  }
  // A frame destroyed while its background thread runs stops it (no hang, no leak).
  {
    const Frame frame(scene, spec);
    frame.start_unshadowed_in_background();
  }
  EXPECT_EQ(plain.irradiance_background_rows(), 0);
}

TEST(Frame, BeautyPngFromRowsIsTheShadedImagesPng) {
  const Scene scene = two_light_scene();
  LightSampleSpec spec;
  spec.k = 2;
  const Frame frame(scene, spec);
  const MethodInfo& info = MethodRegistry::builtin().get("shadow_map");
  const MethodResult result = frame.run(info, resolve_options(info, {}), false);
  const std::vector<const Visibility*> per_light = {&result.per_light[0], &result.per_light[1]};
  const std::filesystem::path dir = std::filesystem::temp_directory_path();
  const std::filesystem::path whole = dir / "penumbra_test_frame_whole.png";
  const std::filesystem::path rows = dir / "penumbra_test_frame_rows.png";
  write_png_rgb(whole, shade(frame, per_light, ShadingMode::modulate));
  const RowShader shader(frame, per_light, ShadingMode::modulate);
  write_png_rgb(rows, scene.camera.width, scene.camera.height,
                [&](int y, Vec3* out) { shader.row(y, out); });
  std::ifstream a(whole, std::ios::binary), b(rows, std::ios::binary);
  const std::string bytes_a((std::istreambuf_iterator<char>(a)), {});
  const std::string bytes_b((std::istreambuf_iterator<char>(b)), {});
  EXPECT_GT(bytes_a.size(), 1000u);
  EXPECT_EQ(bytes_a, bytes_b);
  std::filesystem::remove(whole);
  std::filesystem::remove(rows);
}

}  // namespace
}  // namespace penumbra
