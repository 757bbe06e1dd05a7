// Keyframed animation of a scene: mesh transforms and vertex clips, lights (with video-textured
// emission), the camera; a time range and frame rate. A Scene holds its rest pose and its
// Animation; pose_scene evaluates the still frame at one time.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "penumbra/core/math.hpp"

namespace penumbra {

struct Scene;

template <class T>
struct Keyframe {
  double time_s = 0.0;
  T value{};
};

/// Keys at strictly increasing times. Before the first key the track holds the first value, after
/// the last the last one; in between it interpolates linearly (component-wise for vectors).
template <class T>
struct Track {
  std::vector<Keyframe<T>> keys;

  bool empty() const { return keys.empty(); }
  T at(double time_s) const {
    if (time_s <= keys.front().time_s) return keys.front().value;
    if (time_s >= keys.back().time_s) return keys.back().value;
    size_t hi = 1;
    while (keys[hi].time_s < time_s) ++hi;
    const Keyframe<T>& a = keys[hi - 1];
    const Keyframe<T>& b = keys[hi];
    const double w = (time_s - a.time_s) / (b.time_s - a.time_s);
    return a.value + static_cast<float>(w) * (b.value - a.value);
  }
};

/// A rigid (plus scale) motion of a mesh's rest positions:
///   world = pivot + translate + Rz·Ry·Rx · (scale ∘ (rest − pivot)).
/// Rotation keys are XYZ Euler angles in degrees, interpolated per angle (as animation tools'
/// Euler curves are), so a key pair 0 → 720 turns twice. Empty tracks are the identity.
struct TransformTrack {
  Vec3 pivot{0.0f};
  Track<Vec3> translate;
  Track<Vec3> rotate_deg;
  Track<Vec3> scale;

  bool empty() const { return translate.empty() && rotate_deg.empty() && scale.empty(); }
  Mat4 at(double time_s) const;
};

/// A deforming mesh: the rest positions of every vertex at each key time (same vertex count and
/// order as the mesh, in the scene's world space before its TransformTrack), interpolated linearly
/// per vertex. From a mesh file's own animation (MD2/MD3 frames, glTF morph targets and skins) or
/// generated in code (the `flag` scene's cloth).
struct VertexClip {
  std::string name;
  std::vector<double> times_s;
  std::vector<std::vector<Vec3>> positions;
  /// For a clip from a mesh file (mesh_clips.hpp): the frame rate it was played at (frame k at
  /// times_s[0] + k / source_fps), so a scene file can name it again. 0: generated in code.
  double source_fps = 0.0;
};

struct MeshAnimation {
  int mesh = -1;
  TransformTrack transform;
  std::shared_ptr<const VertexClip> clip;  // null: rigid
};

/// Tracks of one light's parameters (empty: the rest value). A rectangle's edges are animated as
/// vectors; a disk's or sphere's size as its radius.
struct LightAnimation {
  int light = -1;
  Track<Vec3> center;
  Track<Vec3> edge_u;
  Track<Vec3> edge_v;
  Track<Vec3> normal;
  Track<float> radius;
  Track<Vec3> radiance;
  /// A video-textured light: scene textures shown in turn at `emission_fps` from the animation's
  /// start (looping); empty: the light's own emission_texture throughout.
  std::vector<int> emission_frames;
  double emission_fps = 0.0;
};

struct CameraAnimation {
  Track<Vec3> position;
  Track<Vec3> target;
  Track<float> vfov_deg;
  bool empty() const { return position.empty() && target.empty() && vfov_deg.empty(); }
};

struct Animation {
  double start_s = 0.0;
  double end_s = 0.0;
  double fps = 24.0;
  std::vector<MeshAnimation> meshes;
  std::vector<LightAnimation> lights;
  CameraAnimation camera;

  /// No tracks at all: a still scene.
  bool empty() const { return meshes.empty() && lights.empty() && camera.empty(); }
  /// Frames start_s, start_s + 1/fps, ... up to end_s (inclusive, to 1e-9 s).
  int frame_count() const;
  double frame_time(int frame) const { return start_s + static_cast<double>(frame) / fps; }
  /// Whether mesh positions change over time (a BVH or a method's prepared geometry must be
  /// rebuilt per frame); lights and the camera moving alone leave geometry untouched.
  bool moves_geometry() const { return !meshes.empty(); }
  bool moves_lights() const { return !lights.empty(); }
  bool moves_camera() const { return !camera.empty(); }
};

/// Checks an animation against its scene: indices in range, finite values, keys strictly
/// increasing, clips matching their mesh's vertex count, fps > 0 and end ≥ start. Throws Error
/// naming the first problem. validate_scene calls it.
void validate_animation(const Scene& scene);

/// Moves the animation's absolute positions (pivots, clips, light centres, camera) by −offset, as
/// recentre_scene moves the rest pose.
void recentre_animation(Animation& animation, const DVec3& offset);

/// The still scene at `time_s`: `rest` with every track evaluated (clip, then transform; shading
/// normals of deformed meshes recomputed), validated, and its animation cleared.
Scene pose_scene(const Scene& rest, double time_s);

}  // namespace penumbra
