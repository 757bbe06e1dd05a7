// What the viewer shows, as the user (or a script) edits it: the camera orbiting the scene's
// target, the lights' centre, size, shape and brightness, the method and its options. The scene a
// frame renders is the loaded scene with these edits applied (edited_scene), so the same state
// always gives the same frame, and `save_scene` writes exactly what was rendered.
#pragma once

#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "penumbra/core/light_samples.hpp"
#include "penumbra/scene/scene.hpp"

namespace penumbra::viewer {

/// The scene's camera turned around its target: azimuth about the camera's up axis, elevation
/// above the plane normal to it, distance to the target. Until it is moved it gives the scene's
/// camera bit for bit.
class OrbitCamera {
 public:
  explicit OrbitCamera(const Camera& base);
  Camera camera() const;
  void orbit(float d_azimuth_deg, float d_elevation_deg);
  /// Moves target and eye along the image's right and up axes, by fractions of the distance.
  void pan(float right_fraction, float up_fraction);
  /// Distance to the target times `factor` (> 0).
  void zoom(float factor);
  float azimuth_deg() const { return azimuth_deg_; }
  float elevation_deg() const { return elevation_deg_; }
  /// Whether the user has turned, panned or zoomed it (an animated camera then yields to it).
  bool moved() const { return moved_; }

 private:
  Camera base_;
  Vec3 target_, up_, h0_, h1_;  // up_, h0_, h1_: orthonormal, h0_ toward the base eye
  float distance_ = 1.0f, azimuth_deg_ = 0.0f, elevation_deg_ = 0.0f;
  bool moved_ = false;
};

/// Edits of one light, relative to the scene's: centre (world), size factor, shape, brightness.
struct LightEdit {
  Vec3 center{0.0f};
  float scale = 1.0f;  // edges (rect) or radius (disk, sphere) times this
  LightShape shape = LightShape::rect;
  float intensity = 1.0f;  // radiance times this
};

/// The scene's light with `edit` applied. A change of shape keeps the area the light shows a
/// receiver (a disk or sphere of radius r, a square of side r·√π) and the direction it emits
/// toward.
Light edited_light(const Light& base, const LightEdit& edit);

struct ViewState {
  uint64_t generation = 1;  // bumped by every edit that changes a frame
  std::string method;
  std::map<std::string, std::map<std::string, std::string>> options;  // method → key → text
  std::vector<LightEdit> lights;
  OrbitCamera camera;
  LightSampleSpec samples;
  int width = 0, height = 0;  // full resolution
  /// An animated scene: the time shown (seconds of the scene's animation), and whether it plays.
  double time_s = 0.0;
  bool playing = false;

  ViewState(const Scene& scene, std::string method_name, const LightSampleSpec& spec);
  void changed() { ++generation; }
};

/// `base` with `lights` edited and `camera` (validated: throws Error for an edit the scene format
/// would refuse). An animated `base` is first posed at `time_s` (pose_scene): a light's edited
/// centre then moves with its animation (the edit is an offset from the rest pose's centre), and
/// an animated camera is shown unless `camera_moved` (the user's orbit camera wins).
Scene edited_scene(const Scene& base, const std::vector<LightEdit>& lights, const Camera& camera,
                   double time_s = 0.0, bool camera_moved = false);

}  // namespace penumbra::viewer
