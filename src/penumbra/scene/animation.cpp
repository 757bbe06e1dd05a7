#include "penumbra/scene/animation.hpp"

#include <cmath>
#include <glm/gtc/matrix_transform.hpp>
#include <string>

#include "penumbra/core/error.hpp"
#include "penumbra/scene/scene.hpp"

namespace penumbra {

namespace {

void require(bool ok, const std::string& what) {
  if (!ok) throw Error(what);
}

bool finite_value(float x) {
  return std::isfinite(x);
}
bool finite_value(const Vec3& v) {
  return is_finite(v);
}

template <class T>
void check_track(const Track<T>& track, const std::string& who) {
  for (size_t i = 0; i < track.keys.size(); ++i) {
    const Keyframe<T>& key = track.keys[i];
    require(std::isfinite(key.time_s) && finite_value(key.value),
            who + ": key " + std::to_string(i) + " is NaN or infinite");
    require(i == 0 || key.time_s > track.keys[i - 1].time_s,
            who + ": key " + std::to_string(i) + " is not after the key before it");
  }
}

void check_clip(const VertexClip& clip, const Mesh& mesh, const std::string& who) {
  require(!clip.times_s.empty() && clip.times_s.size() == clip.positions.size(),
          who + ": clip " + quote(clip.name) + " has no keys or mismatched key arrays");
  for (size_t k = 0; k < clip.times_s.size(); ++k) {
    require(std::isfinite(clip.times_s[k]) && (k == 0 || clip.times_s[k] > clip.times_s[k - 1]),
            who + ": clip " + quote(clip.name) + " key times are not finite and increasing");
    require(clip.positions[k].size() == mesh.positions.size(),
            who + ": clip " + quote(clip.name) + " has " +
                std::to_string(clip.positions[k].size()) + " vertices, the mesh " +
                std::to_string(mesh.positions.size()));
    for (const Vec3& p : clip.positions[k])
      if (!is_finite(p)) require(false, who + ": clip " + quote(clip.name) + " has NaN positions");
  }
}

/// Per-vertex shading normals from the posed triangles, area-weighted.
void recompute_normals(Mesh& mesh) {
  std::vector<DVec3> sum(mesh.positions.size(), DVec3(0.0));
  for (const Triangle& t : mesh.triangles) {
    const DVec3 a(mesh.positions[t.v[0]]), b(mesh.positions[t.v[1]]), c(mesh.positions[t.v[2]]);
    const DVec3 n = glm::cross(b - a, c - a);
    for (uint32_t v : t.v) sum[v] += n;
  }
  for (size_t i = 0; i < sum.size(); ++i) {
    const double len = glm::length(sum[i]);
    if (len > 0.0 && std::isfinite(len)) mesh.normals[i] = Vec3(sum[i] / len);
  }
}

void apply_clip(const VertexClip& clip, double time_s, Mesh& mesh) {
  const std::vector<double>& t = clip.times_s;
  size_t hi = 0;
  while (hi < t.size() && t[hi] < time_s) ++hi;
  if (hi == 0 || hi == t.size()) {
    mesh.positions = clip.positions[hi == 0 ? 0 : t.size() - 1];
  } else {
    const float w = static_cast<float>((time_s - t[hi - 1]) / (t[hi] - t[hi - 1]));
    const std::vector<Vec3>& a = clip.positions[hi - 1];
    const std::vector<Vec3>& b = clip.positions[hi];
    for (size_t i = 0; i < a.size(); ++i) mesh.positions[i] = a[i] + w * (b[i] - a[i]);
  }
  if (!mesh.normals.empty()) recompute_normals(mesh);
}

void pose_light(const LightAnimation& anim, const Animation& animation, double time_s,
                Light& light) {
  if (!anim.center.empty()) light.center = anim.center.at(time_s);
  if (!anim.edge_u.empty()) light.edge_u = anim.edge_u.at(time_s);
  if (!anim.edge_v.empty()) light.edge_v = anim.edge_v.at(time_s);
  if (!anim.normal.empty()) light.normal = unit_vector(anim.normal.at(time_s));
  if (!anim.radius.empty()) light.radius = anim.radius.at(time_s);
  if (!anim.radiance.empty()) light.radiance = anim.radiance.at(time_s);
  if (!anim.emission_frames.empty()) {
    const double frames = std::floor((time_s - animation.start_s) * anim.emission_fps + 1e-9);
    const auto n = static_cast<long long>(anim.emission_frames.size());
    const long long i = ((static_cast<long long>(frames) % n) + n) % n;
    light.emission_texture = anim.emission_frames[static_cast<size_t>(i)];
  }
}

}  // namespace

Mat4 TransformTrack::at(double time_s) const {
  const Vec3 t = translate.empty() ? Vec3(0.0f) : translate.at(time_s);
  const Vec3 r = rotate_deg.empty() ? Vec3(0.0f) : glm::radians(rotate_deg.at(time_s));
  const Vec3 s = scale.empty() ? Vec3(1.0f) : scale.at(time_s);
  Mat4 m = glm::translate(Mat4(1.0f), pivot + t);
  m = glm::rotate(m, r.z, Vec3(0, 0, 1));
  m = glm::rotate(m, r.y, Vec3(0, 1, 0));
  m = glm::rotate(m, r.x, Vec3(1, 0, 0));
  m = glm::scale(m, s);
  return glm::translate(m, -pivot);
}

int Animation::frame_count() const {
  if (!(fps > 0.0) || !(end_s >= start_s)) return 0;
  return static_cast<int>(std::floor((end_s - start_s) * fps + 1e-9)) + 1;
}

void validate_animation(const Scene& scene) {
  const Animation& a = scene.animation;
  if (a.empty()) return;
  require(std::isfinite(a.fps) && a.fps > 0.0 && a.fps <= 1000.0,
          "animation: fps must be in (0, 1000]");
  require(std::isfinite(a.start_s) && std::isfinite(a.end_s) && a.end_s >= a.start_s,
          "animation: the time range needs finite start <= end");
  require(a.frame_count() <= 100000, "animation: more than 100000 frames");
  for (const MeshAnimation& m : a.meshes) {
    require(m.mesh >= 0 && m.mesh < static_cast<int>(scene.meshes.size()),
            "animation: mesh index out of range");
    const std::string who = "animation of mesh " + quote(scene.meshes[m.mesh].name);
    require(is_finite(m.transform.pivot), who + ": pivot is not finite");
    check_track(m.transform.translate, who + " translate");
    check_track(m.transform.rotate_deg, who + " rotate");
    check_track(m.transform.scale, who + " scale");
    if (m.clip) check_clip(*m.clip, scene.meshes[m.mesh], who);
  }
  for (const LightAnimation& l : a.lights) {
    require(l.light >= 0 && l.light < static_cast<int>(scene.lights.size()),
            "animation: light index out of range");
    const std::string who = "animation of light " + quote(scene.lights[l.light].name);
    check_track(l.center, who + " center");
    check_track(l.edge_u, who + " edge_u");
    check_track(l.edge_v, who + " edge_v");
    check_track(l.normal, who + " normal");
    check_track(l.radius, who + " radius");
    check_track(l.radiance, who + " radiance");
    for (int tex : l.emission_frames)
      require(tex >= 0 && tex < static_cast<int>(scene.textures.size()),
              who + ": emission frame texture out of range");
    require(l.emission_frames.empty() || (std::isfinite(l.emission_fps) && l.emission_fps > 0.0),
            who + ": emission frames need emission_fps > 0");
  }
  check_track(a.camera.position, "animation of the camera position");
  check_track(a.camera.target, "animation of the camera target");
  check_track(a.camera.vfov_deg, "animation of the camera fov");
}

void recentre_animation(Animation& animation, const DVec3& offset) {
  const auto moved = [&](Vec3& p) { p = Vec3(DVec3(p) - offset); };
  for (MeshAnimation& m : animation.meshes) {
    moved(m.transform.pivot);
    if (m.clip) {
      auto clip = std::make_shared<VertexClip>(*m.clip);
      for (std::vector<Vec3>& key : clip->positions)
        for (Vec3& p : key) moved(p);
      m.clip = std::move(clip);
    }
  }
  for (LightAnimation& l : animation.lights)
    for (Keyframe<Vec3>& k : l.center.keys) moved(k.value);
  for (Keyframe<Vec3>& k : animation.camera.position.keys) moved(k.value);
  for (Keyframe<Vec3>& k : animation.camera.target.keys) moved(k.value);
}

Scene pose_scene(const Scene& rest, double time_s) {
  Scene posed = rest;
  const Animation& a = rest.animation;
  for (const MeshAnimation& m : a.meshes) {
    Mesh& mesh = posed.meshes[m.mesh];
    if (m.clip) apply_clip(*m.clip, time_s, mesh);
    if (!m.transform.empty()) transform_mesh(mesh, m.transform.at(time_s));
  }
  for (const LightAnimation& l : a.lights) pose_light(l, a, time_s, posed.lights[l.light]);
  const CameraAnimation& c = a.camera;
  if (!c.position.empty()) posed.camera.position = c.position.at(time_s);
  if (!c.target.empty()) posed.camera.target = c.target.at(time_s);
  if (!c.vfov_deg.empty()) posed.camera.vfov_deg = c.vfov_deg.at(time_s);
  posed.animation = Animation{};
  validate_scene(posed);
  return posed;
}

}  // namespace penumbra
