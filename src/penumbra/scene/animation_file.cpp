#include "penumbra/scene/animation_file.hpp"

#include <cstdio>
#include <map>
#include <sstream>

#include "penumbra/scene/mesh_clips.hpp"
#include "penumbra/scene/mesh_loader.hpp"
#include "penumbra/scene/scene_json.hpp"

namespace penumbra {

namespace {

using namespace scene_json;

/// Key times and the time range: seconds, within ±1e9 (31 years).
constexpr double kMaxTime = 1e9;
/// The most frames an emission sequence (a video-textured light) may name.
constexpr int kMaxEmissionFrames = 10000;

std::string number_text(double x) {
  std::ostringstream out;
  out << x;
  return out.str();
}

/// `[[t, value], ...]`: at least one key, times strictly increasing.
template <class T, class Parse>
Track<T> parse_track(const json& v, const std::string& path, Parse value) {
  if (!v.is_array()) expected(path, "an array of [time, value] keys", v);
  if (v.empty()) fail(path, "must contain at least one key");
  Track<T> track;
  for (size_t i = 0; i < v.size(); ++i) {
    const std::string at = element(path, i);
    if (!v[i].is_array() || v[i].size() != 2) expected(at, "a key [time, value]", v[i]);
    const double t = as_double(v[i][0], element(at, 0), kMaxTime);
    if (i > 0 && !(t > track.keys.back().time_s))
      fail(element(at, 0), "key time " + number_text(t) + " is not after the previous key's (" +
                               number_text(track.keys.back().time_s) + ")");
    track.keys.push_back({t, value(v[i][1], element(at, 1))});
  }
  return track;
}

Track<Vec3> vec3_track(const json& v, const std::string& path) {
  return parse_track<Vec3>(v, path, as_vec3);
}

Track<Vec3> position_track(const json& v, const std::string& path, const DVec3& origin) {
  return parse_track<Vec3>(
      v, path, [&](const json& x, const std::string& p) { return as_position(x, p, origin); });
}

Vec3 as_scale(const json& v, const std::string& path) {
  Vec3 s;
  if (v.is_number()) {
    s = Vec3(as_number(v, path));
  } else if (v.is_array()) {
    s = as_vec3(v, path);
  } else {
    expected(path, "a number or an array of 3 numbers", v);
  }
  if (s.x == 0.0f || s.y == 0.0f || s.z == 0.0f) fail(path, "must be nonzero");
  return s;
}

/// The index of the one element of `items` named `name` (meshes and lights are referred to by
/// name; a name two of them share is ambiguous).
template <class Item>
int find_named(const std::vector<Item>& items, const json& v, const std::string& path,
               const std::string& kind, const std::string& kinds) {
  const std::string name = as_string(v, path);
  std::vector<std::string> names;
  int found = -1;
  for (size_t i = 0; i < items.size(); ++i) {
    names.push_back(items[i].name);
    if (items[i].name != name) continue;
    if (found >= 0)
      fail(path, "two " + kinds + " are named " + in_quotes(name) + ": give them distinct names");
    found = static_cast<int>(i);
  }
  if (found < 0)
    fail(path, "unknown " + kind + " " + in_quotes(name) + did_you_mean(name, names) + " (" +
                   kinds + ": " + join(names) + ")");
  return found;
}

std::shared_ptr<const VertexClip> parse_clip(const Obj& o, const Mesh& mesh,
                                             const Animation& animation) {
  ClipRef ref;
  const json& v = o.req("clip");
  if (v.is_string()) {
    ref.name = as_string(v, o.at("clip"));
  } else if (v.is_number_integer()) {
    ref.index = as_int(v, o.at("clip"), 0, 1 << 20);
  } else {
    expected(o.at("clip"), "a clip name or index", v);
  }
  if (const json* fps = o.find("clip_fps")) {
    ref.fps = as_positive(*fps, o.at("clip_fps"));
    if (ref.fps > 1000.0) fail(o.at("clip_fps"), "must be at most 1000");
  }
  ref.start_s = animation.start_s;
  if (mesh.source_file.empty())
    fail(o.at("clip"), "mesh " + in_quotes(mesh.name) + " is not read from a file");
  try {
    return std::make_shared<VertexClip>(
        load_vertex_clip(mesh.source_file, ref, mesh.source_transform));
  } catch (const Error& e) {
    fail(o.at("clip"), e.what());
  }
}

/// `[[t, "file"], ...]`: the mesh's vertex positions at each time, from mesh files with the
/// mesh's vertex count, placed by the mesh's transform (a generated clip written back).
std::shared_ptr<const VertexClip> parse_vertex_keys(const json& v, const std::string& path,
                                                    const Mesh& mesh, const fs::path& base) {
  if (mesh.source_file.empty())
    fail(path, "mesh " + in_quotes(mesh.name) + " is not read from a file");
  auto clip = std::make_shared<VertexClip>();
  clip->name = mesh.name;
  const Track<std::string> keys = parse_track<std::string>(v, path, as_string);
  for (size_t i = 0; i < keys.keys.size(); ++i) {
    const std::string at = element(element(path, i), 1);
    Mesh frame;
    try {
      frame = load_mesh_file(resolve(base, keys.keys[i].value));
    } catch (const Error& e) {
      fail(at, e.what());
    }
    if (frame.positions.size() != mesh.positions.size())
      fail(at, "has " + std::to_string(frame.positions.size()) + " vertices, the mesh " +
                   std::to_string(mesh.positions.size()));
    transform_mesh(frame, mesh.source_transform);
    clip->times_s.push_back(keys.keys[i].time_s);
    clip->positions.push_back(std::move(frame.positions));
  }
  return clip;
}

MeshAnimation parse_mesh_animation(const json& j, const std::string& path, const Scene& scene,
                                   const Animation& animation, const fs::path& base,
                                   const DVec3& origin) {
  const Obj o(
      j, path,
      {"mesh", "pivot", "translate", "rotate_deg", "scale", "clip", "clip_fps", "vertex_keys"});
  MeshAnimation m;
  m.mesh = find_named(scene.meshes, o.req("mesh"), o.at("mesh"), "mesh", "meshes");
  const Mesh& mesh = scene.meshes[m.mesh];
  if (o.has("pivot")) m.transform.pivot = o.position("pivot", origin);
  if (const json* v = o.find("translate"))
    m.transform.translate = vec3_track(*v, o.at("translate"));
  if (const json* v = o.find("rotate_deg"))
    m.transform.rotate_deg = vec3_track(*v, o.at("rotate_deg"));
  if (const json* v = o.find("scale"))
    m.transform.scale = parse_track<Vec3>(*v, o.at("scale"), as_scale);
  if (o.has("clip_fps") && !o.has("clip")) fail(o.at("clip_fps"), "needs 'clip'");
  if (o.has("clip") && o.has("vertex_keys"))
    fail(path, "give either 'clip' or 'vertex_keys', not both");
  if (o.has("clip")) m.clip = parse_clip(o, mesh, animation);
  if (const json* v = o.find("vertex_keys"))
    m.clip = parse_vertex_keys(*v, o.at("vertex_keys"), mesh, base);
  if (m.transform.empty() && !m.clip)
    fail(path, "animates nothing (give translate, rotate_deg, scale, clip or vertex_keys)");
  return m;
}

/// printf-style `pattern` with one %d or %0Nd (and %% for a percent sign) formatted with `n`.
std::string format_frame(const std::string& pattern, int n, const std::string& path) {
  std::string out;
  int conversions = 0;
  for (size_t i = 0; i < pattern.size(); ++i) {
    if (pattern[i] != '%') {
      out += pattern[i];
      continue;
    }
    size_t k = i + 1;
    if (k < pattern.size() && pattern[k] == '%') {
      out += '%';
      i = k;
      continue;
    }
    int width = 0;
    if (k < pattern.size() && pattern[k] == '0')
      while (++k < pattern.size() && pattern[k] >= '0' && pattern[k] <= '9')
        width = std::min(width * 10 + (pattern[k] - '0'), 99);
    if (k >= pattern.size() || pattern[k] != 'd')
      fail(path, "needs one %d or %0Nd (and %% for a percent sign)");
    char digits[128];
    std::snprintf(digits, sizeof digits, "%0*d", width, n);
    out += digits;
    ++conversions;
    i = k;
  }
  if (conversions != 1) fail(path, "needs exactly one %d or %0Nd");
  return out;
}

std::vector<int> parse_emission_frames(const json& v, const std::string& path,
                                       TextureCache& textures) {
  std::vector<int> frames;
  if (v.is_object()) {
    const Obj o(v, path, {"pattern", "count", "first"});
    const std::string pattern = o.string("pattern");
    const int count = as_int(o.req("count"), o.at("count"), 1, kMaxEmissionFrames);
    const int first = o.integer("first", 0, 0, 1 << 30);
    for (int i = 0; i < count; ++i)
      frames.push_back(textures.emission(json(format_frame(pattern, first + i, o.at("pattern"))),
                                         o.at("pattern")));
    return frames;
  }
  if (!v.is_array()) expected(path, "an array of image files or {pattern, count}", v);
  if (v.empty()) fail(path, "must contain at least one image file");
  if (v.size() > static_cast<size_t>(kMaxEmissionFrames))
    fail(path, "more than " + std::to_string(kMaxEmissionFrames) + " frames");
  for (size_t i = 0; i < v.size(); ++i) frames.push_back(textures.emission(v[i], element(path, i)));
  return frames;
}

LightAnimation parse_light_animation(const json& j, const std::string& path, const Scene& scene,
                                     TextureCache& textures, const DVec3& origin) {
  const Obj o(j, path,
              {"light", "center", "edge_u", "edge_v", "normal", "radius", "radiance",
               "emission_frames", "emission_fps"});
  LightAnimation l;
  l.light = find_named(scene.lights, o.req("light"), o.at("light"), "light", "lights");
  const LightShape shape = scene.lights[l.light].shape;
  const auto only = [&](const char* key, bool ok, const char* kinds) {
    if (o.has(key) && !ok)
      fail(o.at(key), "only a " + std::string(kinds) + " light has it (light " +
                          in_quotes(scene.lights[l.light].name) + " is a " +
                          std::string(to_string(shape)) + ")");
  };
  const bool rect = shape == LightShape::rect;
  only("edge_u", rect, "rect");
  only("edge_v", rect, "rect");
  only("emission_frames", rect, "rect");
  only("emission_fps", rect, "rect");
  only("normal", shape == LightShape::disk, "disk");
  only("radius", shape == LightShape::disk || shape == LightShape::sphere, "disk or sphere");
  if (const json* v = o.find("center")) l.center = position_track(*v, o.at("center"), origin);
  if (const json* v = o.find("edge_u")) l.edge_u = vec3_track(*v, o.at("edge_u"));
  if (const json* v = o.find("edge_v")) l.edge_v = vec3_track(*v, o.at("edge_v"));
  if (const json* v = o.find("normal")) l.normal = vec3_track(*v, o.at("normal"));
  if (const json* v = o.find("radius"))
    l.radius = parse_track<float>(*v, o.at("radius"), as_positive);
  if (const json* v = o.find("radiance"))
    l.radiance = parse_track<Vec3>(*v, o.at("radiance"), [](const json& x, const std::string& p) {
      return as_color(x, p, true);
    });
  if (o.has("emission_frames") != o.has("emission_fps"))
    fail(path, "'emission_frames' and 'emission_fps' go together");
  if (const json* v = o.find("emission_frames")) {
    l.emission_frames = parse_emission_frames(*v, o.at("emission_frames"), textures);
    l.emission_fps = as_positive(o.req("emission_fps"), o.at("emission_fps"));
  }
  return l;
}

CameraAnimation parse_camera_animation(const json& j, const std::string& path,
                                       const DVec3& origin) {
  const Obj o(j, path, {"position", "target", "fov_deg"});
  CameraAnimation c;
  if (const json* v = o.find("position")) c.position = position_track(*v, o.at("position"), origin);
  if (const json* v = o.find("target")) c.target = position_track(*v, o.at("target"), origin);
  if (const json* v = o.find("fov_deg"))
    c.vfov_deg = parse_track<float>(*v, o.at("fov_deg"), [](const json& x, const std::string& p) {
      const float f = as_number(x, p);
      if (!(f > 0.0f && f < 180.0f)) fail(p, "must be in (0, 180) degrees");
      return f;
    });
  return c;
}

}  // namespace

Animation parse_animation(const json& j, const Scene& scene, TextureCache& textures,
                          const fs::path& base, const DVec3& origin) {
  const Obj o(j, "animation", {"start", "end", "fps", "meshes", "lights", "camera"});
  Animation a;
  if (const json* v = o.find("start")) a.start_s = as_double(*v, o.at("start"), kMaxTime);
  a.end_s = as_double(o.req("end"), o.at("end"), kMaxTime);
  if (a.end_s < a.start_s) fail(o.at("end"), "is before start (" + number_text(a.start_s) + ")");
  if (const json* v = o.find("fps")) a.fps = as_double(*v, o.at("fps"), 1e300);
  if (!(a.fps > 0.0 && a.fps <= 1000.0)) fail(o.at("fps"), "must be in (0, 1000]");
  if (a.frame_count() > 100000) fail("animation", "more than 100000 frames");
  std::vector<bool> mesh_taken(scene.meshes.size()), light_taken(scene.lights.size());
  if (const json* v = o.find("meshes")) {
    const json& array = as_array(*v, o.at("meshes"), "mesh animations", "mesh animation");
    for (size_t i = 0; i < array.size(); ++i) {
      const std::string at = element(o.at("meshes"), i);
      a.meshes.push_back(parse_mesh_animation(array[i], at, scene, a, base, origin));
      if (mesh_taken[a.meshes.back().mesh]) fail(at + ".mesh", "animated twice");
      mesh_taken[a.meshes.back().mesh] = true;
    }
  }
  if (const json* v = o.find("lights")) {
    const json& array = as_array(*v, o.at("lights"), "light animations", "light animation");
    for (size_t i = 0; i < array.size(); ++i) {
      const std::string at = element(o.at("lights"), i);
      a.lights.push_back(parse_light_animation(array[i], at, scene, textures, origin));
      if (light_taken[a.lights.back().light]) fail(at + ".light", "animated twice");
      light_taken[a.lights.back().light] = true;
    }
  }
  if (const json* v = o.find("camera"))
    a.camera = parse_camera_animation(*v, o.at("camera"), origin);
  return a;
}

namespace {

json position_json(const Vec3& v, const DVec3& origin) {
  const DVec3 w = DVec3(v) + origin;
  if (origin == DVec3(0.0)) return json::array({v.x, v.y, v.z});
  return json::array({w.x, w.y, w.z});
}

json vec3_json(const Vec3& v) {
  return json::array({v.x, v.y, v.z});
}

template <class T, class Write>
void put_track(json& into, const char* key, const Track<T>& track, Write value) {
  if (track.empty()) return;
  json keys = json::array();
  for (const Keyframe<T>& k : track.keys) keys.push_back(json::array({k.time_s, value(k.value)}));
  into[key] = std::move(keys);
}

void put_vec3_track(json& into, const char* key, const Track<Vec3>& track) {
  put_track(into, key, track, vec3_json);
}

void put_position_track(json& into, const char* key, const Track<Vec3>& track,
                        const DVec3& origin) {
  put_track(into, key, track, [&](const Vec3& v) { return position_json(v, origin); });
}

/// The clip by name when it is one of its file's (same frames and timing), else by its keys.
void put_clip(json& into, const MeshAnimation& m, const AnimationAssets& assets) {
  const VertexClip& clip = *m.clip;
  if (clip.source_fps > 0.0 && assets.mesh_written_as_file.at(m.mesh)) {
    into["clip"] = clip.name;
    into["clip_fps"] = clip.source_fps;
    return;
  }
  json keys = json::array();
  for (size_t k = 0; k < clip.times_s.size(); ++k)
    keys.push_back(json::array({clip.times_s[k], assets.clip_key(m.mesh, k, clip.positions[k])}));
  into["vertex_keys"] = std::move(keys);
}

json light_animation_json(const Scene& scene, const LightAnimation& l,
                          const AnimationAssets& assets) {
  json j = {{"light", assets.light_names.at(l.light)}};
  put_position_track(j, "center", l.center, scene.origin);
  put_vec3_track(j, "edge_u", l.edge_u);
  put_vec3_track(j, "edge_v", l.edge_v);
  put_vec3_track(j, "normal", l.normal);
  put_track(j, "radius", l.radius, [](float r) { return json(r); });
  put_vec3_track(j, "radiance", l.radiance);
  if (!l.emission_frames.empty()) {
    json frames = json::array();
    for (int t : l.emission_frames) frames.push_back(assets.emission_texture(t));
    j["emission_frames"] = std::move(frames);
    j["emission_fps"] = l.emission_fps;
  }
  return j;
}

}  // namespace

json animation_json(const Scene& scene, const AnimationAssets& assets) {
  const Animation& a = scene.animation;
  const Animation still;
  if (a.empty() && a.start_s == still.start_s && a.end_s == still.end_s && a.fps == still.fps)
    return nullptr;
  json j = {{"start", a.start_s}, {"end", a.end_s}, {"fps", a.fps}};
  if (!a.meshes.empty()) j["meshes"] = json::array();
  for (const MeshAnimation& m : a.meshes) {
    json jm = {{"mesh", assets.mesh_names.at(m.mesh)}};
    if (m.transform.pivot != Vec3(0.0f) || scene.origin != DVec3(0.0))
      jm["pivot"] = position_json(m.transform.pivot, scene.origin);
    put_vec3_track(jm, "translate", m.transform.translate);
    put_vec3_track(jm, "rotate_deg", m.transform.rotate_deg);
    put_vec3_track(jm, "scale", m.transform.scale);
    if (m.clip) put_clip(jm, m, assets);
    j["meshes"].push_back(std::move(jm));
  }
  if (!a.lights.empty()) j["lights"] = json::array();
  for (const LightAnimation& l : a.lights)
    j["lights"].push_back(light_animation_json(scene, l, assets));
  if (!a.camera.empty()) {
    json c = json::object();
    put_position_track(c, "position", a.camera.position, scene.origin);
    put_position_track(c, "target", a.camera.target, scene.origin);
    put_track(c, "fov_deg", a.camera.vfov_deg, [](float f) { return json(f); });
    j["camera"] = std::move(c);
  }
  return j;
}

}  // namespace penumbra
