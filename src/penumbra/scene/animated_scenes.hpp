// The built-in animated scenes (seeded or procedural, no downloads): a light circling and growing
// over the bunny, the alpha-textured fence spinning, a waving flag (a deforming mesh that shadows
// itself), and a marquee (a video-textured light). Their rest pose is frame 0.
#pragma once

#include "penumbra/scene/scene.hpp"

namespace penumbra {

/// `bunny_orbit`: the benchmark bunny layout (a procedural bumpy ball when the bunny is not
/// fetched); the square light circles the model's vertical axis once while its side grows.
struct BunnyOrbit {
  double duration_s = 4.0;
  float orbit_radius = 0.6f;  // of the light centre's circle, around the model's vertical axis
  float light_height = 1.5f;  // above the model's centre
  float side_start = 0.3f, side_end = 0.7f;  // the square light's side grows linearly
};
inline constexpr BunnyOrbit kBunnyOrbit{};
Scene make_bunny_orbit_scene();

/// `fence_spin`: the `fence` scene with its fence turning about the vertical through its centre.
struct FenceSpin {
  double duration_s = 3.0;
  float degrees_per_s = 60.0f;
};
inline constexpr FenceSpin kFenceSpin{};
Scene make_fence_spin_scene();

/// `flag`: a cloth grid on a pole, waving (a travelling wave whose amplitude grows away from the
/// pole), over the ground.
struct Flag {
  double duration_s = 2.0;
  int columns = 48, rows = 32;  // grid quads: 2 · 48 · 32 = 3072 triangles
  float width = 1.2f, height = 0.8f;
  float amplitude = 0.12f;  // of the wave at the free edge, world units
  float wavelength = 0.9f;  // along the flag
  double period_s = 1.0;    // of the wave: the clip loops every second
};
inline constexpr Flag kFlag{};
Scene make_flag_scene();
/// The cloth's vertex positions at time t (the clip's keys are these at every frame).
std::vector<Vec3> flag_positions(double time_s);

/// `marquee`: a long rectangle light whose emission texture cycles through stripes moving along
/// it, over a row of boxes and a sphere.
struct Marquee {
  double duration_s = 2.0;
  int frames = 8;           // emission textures, shown in turn
  double frame_fps = 12.0;  // each frame shows for 1/12 s: the cycle repeats three times in 2 s
  int texture_width = 64, texture_height = 8;
};
inline constexpr Marquee kMarquee{};
Scene make_marquee_scene();

}  // namespace penumbra
