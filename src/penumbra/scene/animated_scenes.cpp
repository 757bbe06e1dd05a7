#include "penumbra/scene/animated_scenes.hpp"

#include <cmath>

#include "penumbra/scene/builtin_scenes.hpp"
#include "penumbra/scene/mesh_loader.hpp"
#include "penumbra/scene/model_paths.hpp"
#include "penumbra/scene/model_scene.hpp"
#include "penumbra/scene/scene_parts.hpp"
#include "penumbra/scene/shapes.hpp"

namespace penumbra {

namespace {

constexpr double kFps = 24.0;
constexpr float kTwoPi = 2.0f * static_cast<float>(kPi);

Animation timeline(double duration_s) {
  Animation a;
  a.start_s = 0.0;
  a.end_s = duration_s;
  a.fps = kFps;
  return a;
}

/// A closed ball with low bumps, of the bunny's size once framed: stands in for the bunny when it
/// is not fetched (a dense closed mesh casting a soft shadow, like herd's stand-ins).
Mesh bumpy_ball() {
  Mesh m = make_sphere(Vec3(0.0f), 1.0f, 64, 128);
  for (size_t i = 0; i < m.positions.size(); ++i) {
    const Vec3 n = m.normals[i];
    const float bump = 0.06f * std::sin(7.0f * n.x + 1.3f) * std::sin(5.0f * n.y + 0.4f) *
                       std::sin(6.0f * n.z + 2.1f);
    m.positions[i] += bump * n;
  }
  m.normals.clear();
  return m;
}

}  // namespace

Scene make_bunny_orbit_scene() {
  const BunnyOrbit o = kBunnyOrbit;
  const auto bunny = find_model("bunny00.off");
  ModelFraming layout;
  layout.fit_camera = false;
  Scene s = bunny ? frame_model(load_mesh_file(*bunny), "bunny_orbit", layout, *bunny)
                  : frame_model(bumpy_ball(), "bunny_orbit", layout);
  s.name = "bunny_orbit";
  s.meshes[1].name = "model";
  s.animation = timeline(o.duration_s);
  const Vec3 axis = s.camera.target;  // the model's centre
  LightAnimation l;
  l.light = 0;
  const int frames = s.animation.frame_count();
  for (int f = 0; f < frames; ++f) {
    // A key per frame: the centre lies on the circle at every frame time, and the square keeps
    // the irradiance of the benchmark light (power ∝ 1 / area) as it grows.
    const double t = s.animation.frame_time(f);
    const float phase = kTwoPi * static_cast<float>(t / o.duration_s);
    const float side =
        o.side_start + (o.side_end - o.side_start) * static_cast<float>(t / o.duration_s);
    l.center.keys.push_back({t, axis + Vec3(o.orbit_radius * std::cos(phase), o.light_height,
                                            o.orbit_radius * std::sin(phase))});
    l.edge_u.keys.push_back({t, Vec3(side, 0, 0)});
    l.edge_v.keys.push_back({t, Vec3(0, 0, side)});
    l.radiance.keys.push_back({t, Vec3(16.0f * 0.25f / (side * side))});
  }
  s.lights[0].center = l.center.keys[0].value;
  s.lights[0].edge_u = l.edge_u.keys[0].value;
  s.lights[0].edge_v = l.edge_v.keys[0].value;
  s.lights[0].radiance = l.radiance.keys[0].value;
  s.animation.lights.push_back(std::move(l));
  return s;
}

Scene make_fence_spin_scene() {
  const FenceSpin f = kFenceSpin;
  Scene s = make_builtin_scene("fence");
  s.name = "fence_spin";
  s.animation = timeline(f.duration_s);
  MeshAnimation m;
  m.mesh = 1;  // the fence quad, centred at (0, 1, 0)
  m.transform.pivot = s.meshes[1].bounds().center();
  m.transform.rotate_deg.keys = {
      {0.0, Vec3(0.0f)},
      {f.duration_s, Vec3(0.0f, f.degrees_per_s * static_cast<float>(f.duration_s), 0.0f)}};
  s.animation.meshes.push_back(std::move(m));
  return s;
}

std::vector<Vec3> flag_positions(double time_s) {
  const Flag f = kFlag;
  const float phase_t = kTwoPi * static_cast<float>(std::fmod(time_s / f.period_s, 1.0));
  std::vector<Vec3> out;
  out.reserve(static_cast<size_t>((f.columns + 1) * (f.rows + 1)));
  for (int r = 0; r <= f.rows; ++r)
    for (int c = 0; c <= f.columns; ++c) {
      const float u = static_cast<float>(c) / static_cast<float>(f.columns);
      const float v = static_cast<float>(r) / static_cast<float>(f.rows);
      const float x = 0.02f + u * f.width;
      // The wave travels away from the pole; its amplitude grows from 0 at the pole (held there)
      // and the crests lean with height, so the cloth folds over itself.
      const float wave = std::sin(kTwoPi * (u * f.width / f.wavelength) - phase_t + 1.2f * v);
      out.emplace_back(x, 1.1f + v * f.height, f.amplitude * u * wave);
    }
  return out;
}

Scene make_flag_scene() {
  const Flag f = kFlag;
  Scene s;
  s.name = "flag";
  add_ground(s);
  add_mesh(s, make_box(Vec3(0.0f, 1.0f, 0.0f), Vec3(0.015f, 1.0f, 0.015f)), "pole",
           add_material(s, "pole", Vec3(0.5f, 0.45f, 0.4f)));
  Mesh cloth;
  cloth.positions = flag_positions(0.0);
  const auto vertex = [&](int c, int r) { return static_cast<uint32_t>(r * (f.columns + 1) + c); };
  for (int r = 0; r < f.rows; ++r)
    for (int c = 0; c < f.columns; ++c) {
      cloth.triangles.push_back({{vertex(c, r), vertex(c + 1, r), vertex(c + 1, r + 1)}});
      cloth.triangles.push_back({{vertex(c, r), vertex(c + 1, r + 1), vertex(c, r + 1)}});
    }
  add_mesh(s, std::move(cloth), "cloth", add_material(s, "cloth", Vec3(0.75f, 0.2f, 0.15f)));
  // In front of the cloth and above: the folds shadow the cloth, the cloth the ground behind it.
  s.lights.push_back(square_light(Vec3(0.6f, 3.0f, 1.2f), 0.6f, 6.0f));
  s.camera.position = Vec3(1.9f, 1.7f, 3.0f);
  s.camera.target = Vec3(0.5f, 0.9f, 0.0f);

  s.animation = timeline(f.duration_s);
  auto clip = std::make_shared<VertexClip>();
  clip->name = "wave";
  for (int k = 0; k < s.animation.frame_count(); ++k) {
    clip->times_s.push_back(s.animation.frame_time(k));
    clip->positions.push_back(flag_positions(clip->times_s.back()));
  }
  MeshAnimation m;
  m.mesh = 2;
  m.clip = std::move(clip);
  s.animation.meshes.push_back(std::move(m));
  return s;
}

namespace {

/// An 8-bit sRGB value as the scene loader decodes it: a marquee written to PNG loads back to the
/// same texels.
float srgb8_to_linear(int byte) {
  const float c = static_cast<float>(byte) / 255.0f;
  return c <= 0.04045f ? c / 12.92f : std::pow((c + 0.055f) / 1.055f, 2.4f);
}

/// Frame k of the marquee: warm stripes 8 texels wide, moved 2 texels along u per frame, so the
/// 8 frames make one seamless cycle of the 16-texel pattern.
Texture marquee_frame(int k) {
  const Marquee m = kMarquee;
  Texture t;
  t.name = "marquee_" + std::to_string(k);
  t.width = m.texture_width;
  t.height = m.texture_height;
  t.channels = 3;
  t.texels.resize(static_cast<size_t>(t.width) * t.height * 3);
  for (int y = 0; y < t.height; ++y)
    for (int x = 0; x < t.width; ++x) {
      const bool lit = ((x + 2 * k) / 8) % 2 == 0;
      const Vec3 c = lit ? Vec3(srgb8_to_linear(255), srgb8_to_linear(230), srgb8_to_linear(180))
                         : Vec3(srgb8_to_linear(60), srgb8_to_linear(50), srgb8_to_linear(40));
      float* texel = &t.texels[(static_cast<size_t>(y) * t.width + x) * 3];
      texel[0] = c.x, texel[1] = c.y, texel[2] = c.z;
    }
  return t;
}

}  // namespace

Scene make_marquee_scene() {
  const Marquee mq = kMarquee;
  Scene s;
  s.name = "marquee";
  add_ground(s);
  const int red = add_material(s, "boxes", Vec3(0.7f, 0.3f, 0.25f));
  Mesh boxes;
  for (int i = -1; i <= 1; ++i)
    append_mesh(boxes, make_box(Vec3(0.6f * static_cast<float>(i),
                                     0.25f + 0.1f * static_cast<float>(i + 1), 0.0f),
                                Vec3(0.12f, 0.25f + 0.1f * static_cast<float>(i + 1), 0.12f)));
  add_mesh(s, std::move(boxes), "boxes", red);
  add_mesh(s, make_sphere(Vec3(0.25f, 0.9f, 0.25f), 0.15f, 16, 32), "ball",
           add_material(s, "ball", Vec3(0.3f, 0.5f, 0.8f)));
  LightAnimation l;
  l.light = 0;
  l.emission_fps = mq.frame_fps;
  for (int k = 0; k < mq.frames; ++k) {
    s.textures.push_back(marquee_frame(k));
    l.emission_frames.push_back(static_cast<int>(s.textures.size() - 1));
  }
  Light light = square_light(Vec3(0.0f, 2.2f, 0.0f), 1.0f, 8.0f);
  light.edge_u = Vec3(1.6f, 0, 0);
  light.edge_v = Vec3(0, 0, 0.4f);
  light.emission_texture = l.emission_frames[0];
  s.lights.push_back(light);
  s.camera.position = Vec3(0.4f, 2.2f, 3.0f);
  s.camera.target = Vec3(0.0f, 0.3f, 0.0f);
  s.animation = timeline(mq.duration_s);
  s.animation.lights.push_back(std::move(l));
  return s;
}

}  // namespace penumbra
