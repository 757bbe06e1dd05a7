// Penumbra through its public API: a scene built in code, rendered by `gears` and by `raytrace`
// on the same light samples (their per-sample masks must agree), measured against `exact`; then
// the light moves and the same Renderer renders again, reusing what it prepared.
#include <cstdio>
#include <cstring>
#include <penumbra/penumbra.hpp>

namespace {

penumbra::Mesh quad(penumbra::Vec3 centre, penumbra::Vec3 half_u, penumbra::Vec3 half_v) {
  penumbra::Mesh m;
  m.positions = {centre - half_u - half_v, centre + half_u - half_v, centre + half_u + half_v,
                 centre - half_u + half_v};
  m.triangles = {{{0, 1, 2}}, {{0, 2, 3}}};
  return m;
}

/// A square occluder over a ground plane, under a square light.
penumbra::Scene make_scene() {
  using penumbra::Vec3;
  penumbra::Scene scene;
  scene.name = "embed";
  scene.materials.push_back({});
  scene.meshes.push_back(quad(Vec3(0, 0, 0), Vec3(0, 0, 2), Vec3(2, 0, 0)));  // faces +y
  scene.meshes.push_back(quad(Vec3(0, 1, 0), Vec3(0, 0, 0.5f), Vec3(0.5f, 0, 0)));
  penumbra::Light light;
  light.center = Vec3(0, 3, 0);
  light.edge_u = Vec3(1, 0, 0);
  light.edge_v = Vec3(0, 0, 1);  // emits toward u × v = −y
  light.radiance = Vec3(4.0f);
  scene.lights.push_back(light);
  scene.camera.position = Vec3(0, 2.6f, 3.2f);
  scene.camera.target = Vec3(0, 0, 0.2f);
  return scene;
}

}  // namespace

int main() {
  try {
    penumbra::Scene scene = make_scene();
    penumbra::RenderSettings settings;
    settings.width = 96;
    settings.height = 72;
    settings.samples = 8;
    settings.masks = true;

    penumbra::Renderer renderer;
    settings.method = "exact";
    const penumbra::RenderResult exact = renderer.render(scene, settings);
    settings.method = "raytrace";
    const penumbra::RenderResult rays = renderer.render(scene, settings);
    settings.method = "gears";
    const penumbra::RenderResult gears = renderer.render(scene, settings);

    const penumbra::SampleMasks& a = *gears.lights[0].masks;
    const penumbra::SampleMasks& b = *rays.lights[0].masks;
    const size_t words = static_cast<size_t>(a.width()) * a.height() * a.words_per_pixel();
    const bool masks_equal = std::memcmp(a.pixel(0), b.pixel(0), words * 8) == 0;
    const penumbra::ErrorStats error = penumbra::compare(exact, gears).front();
    std::printf("penumbra %s: gears %.1f ms, masks %s raytrace's, mean |V - exact| %.4f\n",
                penumbra::version(), gears.method_ms, masks_equal ? "equal" : "DIFFER FROM",
                error.mean_abs);

    scene.lights[0].center.x += 0.5f;  // only the light moves: nothing is prepared again
    const penumbra::RenderResult moved = renderer.render(scene, settings);
    std::printf("light moved: BVH %.1f ms, prepare %.1f ms, gears %.1f ms\n",
                moved.frame_ms.at("bvh_build_ms"), moved.prepare_ms, moved.method_ms);

    const bool ok = masks_equal && error.mean_abs < 0.05 && error.pixels > 0 &&
                    moved.frame_ms.at("bvh_build_ms") == 0.0 && moved.prepare_ms == 0.0;
    return ok ? 0 : 1;
  } catch (const penumbra::Error& e) {
    std::fprintf(stderr, "embed: error: %s\n", e.what());
    return 1;
  }
}
