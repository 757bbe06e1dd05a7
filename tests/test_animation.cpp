// Keyframed animation: track interpolation, posing a scene at a time, validation errors.
#include <gtest/gtest.h>

#include "penumbra/core/error.hpp"
#include "penumbra/scene/builtin_scenes.hpp"
#include "penumbra/scene/scene.hpp"

namespace penumbra {
namespace {

TEST(Animation, TrackHoldsEndsAndInterpolatesLinearly) {
  Track<float> t{{{1.0, 2.0f}, {3.0, 6.0f}}};
  EXPECT_EQ(t.at(0.0), 2.0f);
  EXPECT_EQ(t.at(2.0), 4.0f);
  EXPECT_EQ(t.at(9.0), 6.0f);
}

TEST(Animation, FrameCountIncludesBothEnds) {
  Animation a;
  a.start_s = 0.0;
  a.end_s = 1.0;
  a.fps = 24.0;
  EXPECT_EQ(a.frame_count(), 25);
  EXPECT_DOUBLE_EQ(a.frame_time(12), 0.5);
}

TEST(Animation, PoseMovesMeshLightAndCamera) {
  Scene rest = make_builtin_scene("quad");
  MeshAnimation m;
  m.mesh = 0;
  m.transform.translate.keys = {{0.0, Vec3(0.0f)}, {1.0, Vec3(0.0f, 0.0f, 2.0f)}};
  rest.animation.end_s = 1.0;
  rest.animation.meshes.push_back(m);
  LightAnimation l;
  l.light = 0;
  l.center.keys = {{0.0, rest.lights[0].center}, {1.0, rest.lights[0].center + Vec3(1, 0, 0)}};
  rest.animation.lights.push_back(l);
  rest.animation.camera.vfov_deg.keys = {{0.0, 30.0f}, {1.0, 50.0f}};
  validate_scene(rest);

  const Scene posed = pose_scene(rest, 0.5);
  EXPECT_TRUE(posed.animation.empty());
  for (size_t i = 0; i < rest.meshes[0].positions.size(); ++i)
    EXPECT_EQ(posed.meshes[0].positions[i], rest.meshes[0].positions[i] + Vec3(0, 0, 1));
  EXPECT_EQ(posed.lights[0].center, rest.lights[0].center + Vec3(0.5f, 0, 0));
  EXPECT_FLOAT_EQ(posed.camera.vfov_deg, 40.0f);
  EXPECT_EQ(posed.meshes[1].positions, rest.meshes[1].positions);
}

TEST(Animation, RejectsKeysOutOfOrderAndNaN) {
  Scene s = make_builtin_scene("quad");
  s.animation.end_s = 1.0;
  s.animation.camera.vfov_deg.keys = {{0.5, 30.0f}, {0.25, 50.0f}};
  EXPECT_THROW(validate_scene(s), Error);
  s.animation.camera.vfov_deg.keys = {{0.0, std::nanf("")}};
  EXPECT_THROW(validate_scene(s), Error);
}

}  // namespace
}  // namespace penumbra
