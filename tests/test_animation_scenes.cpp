// The built-in animated scenes: each poses to the motion it is built for, checked in numbers.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "penumbra/scene/animated_scenes.hpp"
#include "penumbra/scene/builtin_scenes.hpp"
#include "penumbra/scene/model_paths.hpp"

namespace penumbra {
namespace {

float max_displacement(const std::vector<Vec3>& a, const std::vector<Vec3>& b) {
  float d = 0.0f;
  for (size_t i = 0; i < a.size(); ++i) d = std::max(d, glm::length(a[i] - b[i]));
  return d;
}

TEST(AnimatedScenes, EachHasATimeRangeAndItsRestPoseIsFrameZero) {
  for (const char* name : {"bunny_orbit", "fence_spin", "flag", "marquee"}) {
    SCOPED_TRACE(name);
    const Scene s = make_builtin_scene(name);
    EXPECT_EQ(s.animation.fps, 24.0);
    EXPECT_GE(s.animation.end_s - s.animation.start_s, 2.0);
    EXPECT_LE(s.animation.end_s - s.animation.start_s, 4.0);
    EXPECT_FALSE(s.animation.empty());
    EXPECT_LE(s.triangle_count(), 80000u);
    const Scene frame0 = pose_scene(s, s.animation.start_s);
    for (size_t m = 0; m < s.meshes.size(); ++m)
      EXPECT_LT(max_displacement(s.meshes[m].positions, frame0.meshes[m].positions), 1e-6f);
    for (size_t l = 0; l < s.lights.size(); ++l) {
      EXPECT_EQ(s.lights[l].center, frame0.lights[l].center);
      EXPECT_EQ(s.lights[l].emission_texture, frame0.lights[l].emission_texture);
    }
    EXPECT_FALSE(builtin_scene_origin(name).empty());
  }
}

TEST(AnimatedScenes, BunnyOrbitLightCirclesAndGrows) {
  const Scene s = make_builtin_scene("bunny_orbit");
  const BunnyOrbit o = kBunnyOrbit;
  const Vec3 axis = s.camera.target;
  EXPECT_EQ(s.animation.frame_count(), 97);
  for (double t : {0.0, 1.0, 1.5, 2.0, 3.0}) {
    SCOPED_TRACE(t);
    const Scene posed = pose_scene(s, t);
    const Light& l = posed.lights[0];
    const Vec3 offset = l.center - axis;
    EXPECT_NEAR(std::hypot(offset.x, offset.z), o.orbit_radius, 1e-5f);
    EXPECT_NEAR(offset.y, o.light_height, 1e-5f);
    const float angle = std::atan2(offset.z, offset.x);
    const float expected = static_cast<float>(2.0 * kPi * t / o.duration_s);
    EXPECT_NEAR(std::remainder(angle - expected, 2.0f * static_cast<float>(kPi)), 0.0f, 1e-5f);
    const float side = o.side_start + (o.side_end - o.side_start) * static_cast<float>(t / 4.0);
    EXPECT_NEAR(glm::length(l.edge_u), side, 1e-6f);
    // Constant power: radiance × area.
    EXPECT_NEAR(l.radiance.x * side * side, 16.0f * 0.25f, 1e-4f);
  }
  // A quarter turn moves the light by a chord of √2 · radius.
  EXPECT_NEAR(glm::length(pose_scene(s, 1.0).lights[0].center - s.lights[0].center),
              std::sqrt(2.0f) * o.orbit_radius, 1e-5f);
}

TEST(AnimatedScenes, FenceSpinTurnsAtSixtyDegreesPerSecond) {
  const Scene s = make_builtin_scene("fence_spin");
  const Mesh& rest = s.meshes[1];
  const Vec3 pivot = rest.bounds().center();
  for (double t : {0.5, 1.5, 2.25}) {
    SCOPED_TRACE(t);
    const Scene scene = pose_scene(s, t);
    const Mesh& posed = scene.meshes[1];
    const float angle = glm::radians(60.0f * static_cast<float>(t));
    for (size_t i = 0; i < rest.positions.size(); ++i) {
      // About +y (right-handed): x' = x cos + z sin, z' = −x sin + z cos.
      const Vec3 d = rest.positions[i] - pivot;
      const Vec3 expected = pivot + Vec3(d.x * std::cos(angle) + d.z * std::sin(angle), d.y,
                                         -d.x * std::sin(angle) + d.z * std::cos(angle));
      EXPECT_LT(glm::length(posed.positions[i] - expected), 1e-5f);
    }
  }
  // The ground stays.
  EXPECT_EQ(pose_scene(s, 1.0).meshes[0].positions, s.meshes[0].positions);
}

TEST(AnimatedScenes, FlagWavesAndHoldsAtThePole) {
  const Scene s = make_builtin_scene("flag");
  const Mesh& cloth = s.meshes[2];
  ASSERT_EQ(cloth.name, "cloth");
  EXPECT_EQ(cloth.positions.size(), 49u * 33u);
  const Scene quarter = pose_scene(s, 0.25), half = pose_scene(s, 0.5);
  // Measured: over half a period the free edge swings by nearly twice the amplitude (0.24; the
  // grid samples the crest at 0.2265).
  EXPECT_NEAR(max_displacement(cloth.positions, half.meshes[2].positions), 0.2265f, 1e-3f);
  EXPECT_GT(max_displacement(cloth.positions, quarter.meshes[2].positions), 0.1f);
  for (size_t i = 0; i < cloth.positions.size(); i += 49)  // column 0: at the pole
    EXPECT_EQ(cloth.positions[i], half.meshes[2].positions[i]);
  // The wave's period is 1 s: t = 1 is the rest pose again.
  EXPECT_LT(max_displacement(cloth.positions, pose_scene(s, 1.0).meshes[2].positions), 1e-5f);
  // Shading normals are recomputed on the posed cloth only where it had some (none: flat).
  EXPECT_TRUE(half.meshes[2].normals.empty());
}

TEST(AnimatedScenes, MarqueeCyclesItsEmissionFrames) {
  const Scene s = make_builtin_scene("marquee");
  const Marquee m = kMarquee;
  const std::vector<int>& frames = s.animation.lights[0].emission_frames;
  ASSERT_EQ(frames.size(), static_cast<size_t>(m.frames));
  for (int k : {0, 1, 5, 8, 13}) {
    const double t = (k + 0.5) / m.frame_fps;
    EXPECT_EQ(pose_scene(s, t).lights[0].emission_texture, frames[k % m.frames]) << k;
  }
  // Consecutive frames differ: the stripes move 2 texels.
  const Texture& a = s.textures[frames[0]];
  const Texture& b = s.textures[frames[1]];
  EXPECT_NE(a.texels, b.texels);
  EXPECT_EQ(a.channel(2, 0, 0), b.channel(0, 0, 0));
  EXPECT_EQ(s.lights[0].center, pose_scene(s, 1.0).lights[0].center);
}

}  // namespace
}  // namespace penumbra
