// Running methods on small frames of built-in scenes, for tests.
#pragma once

#include <map>
#include <memory>
#include <string>

#include "penumbra/metrics/error_metrics.hpp"
#include "penumbra/pipeline/frame.hpp"
#include "penumbra/pipeline/outputs.hpp"
#include "penumbra/scene/builtin_scenes.hpp"

namespace penumbra::test {

/// A scene and a frame over it (the frame points into the scene, so they live together).
struct TestFrame {
  std::unique_ptr<Scene> scene;
  std::unique_ptr<Frame> frame;

  MethodResult run(const std::string& method,
                   const std::map<std::string, std::string>& options = {},
                   bool want_masks = false) const {
    const MethodInfo& info = MethodRegistry::builtin().get(method);
    return frame->run(info, resolve_options(info, options), want_masks);
  }
};

/// One grid sample at the light centre: raytrace's hard shadow, the point the hard methods use.
inline LightSampleSpec centre_sample() {
  LightSampleSpec s;
  s.pattern = SamplePattern::grid;
  s.k = 1;
  return s;
}

inline TestFrame make_test_frame(Scene scene, int width, int height, const LightSampleSpec& spec) {
  TestFrame t;
  scene.camera.width = width;
  scene.camera.height = height;
  t.scene = std::make_unique<Scene>(std::move(scene));
  t.frame = std::make_unique<Frame>(*t.scene, spec);
  return t;
}

inline TestFrame make_test_frame(const std::string& builtin, int width, int height,
                                 const LightSampleSpec& spec) {
  return make_test_frame(make_builtin_scene(builtin), width, height, spec);
}

}  // namespace penumbra::test
