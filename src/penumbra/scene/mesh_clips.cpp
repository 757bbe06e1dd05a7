#include "penumbra/scene/mesh_clips.hpp"

#include <cctype>
#include <cmath>

#include "penumbra/core/error.hpp"
#include "penumbra/scene/gltf_morph.hpp"
#include "penumbra/scene/md2_file.hpp"
#include "penumbra/scene/mesh_loader.hpp"

namespace penumbra {

namespace {

/// A frame's clip: its name without the frame number, at most two trailing digits (Quake II
/// names frames "run1".."run6" or "stand01"; "death101" and "death201" are clips "death1" and
/// "death2").
std::string clip_of(const std::string& frame_name) {
  size_t end = frame_name.size();
  for (int i = 0; i < 2 && end > 1 && std::isdigit(static_cast<unsigned char>(frame_name[end - 1]));
       ++i)
    --end;
  return frame_name.substr(0, end);
}

std::vector<ClipInfo> clips_of(const std::vector<std::string>& frame_names) {
  std::vector<ClipInfo> clips;
  for (size_t f = 0; f < frame_names.size(); ++f) {
    const std::string name = clip_of(frame_names[f]);
    if (clips.empty() || clips.back().name != name) clips.push_back({name, static_cast<int>(f), 0});
    ++clips.back().frame_count;
  }
  return clips;
}

std::string extension_of(const std::filesystem::path& path) {
  std::string ext = path.extension().string();
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return ext;
}

bool is_md2(const std::filesystem::path& path) {
  return extension_of(path) == ".md2";
}

bool is_gltf(const std::filesystem::path& path) {
  return extension_of(path) == ".gltf" || extension_of(path) == ".glb";
}

/// The file's morph animations, read after load_mesh_file has validated it.
std::vector<MorphClip> morph_clips(const std::filesystem::path& path) {
  const Mesh rest = load_mesh_file(path);
  return read_gltf_morph_clips(path, rest.positions.size());
}

std::vector<ClipInfo> infos_of(const std::vector<MorphClip>& clips) {
  std::vector<ClipInfo> out;
  for (const MorphClip& c : clips) out.push_back({c.name, 0, static_cast<int>(c.times_s.size())});
  return out;
}

std::string file_bytes(const std::filesystem::path& path) {
  return read_mesh_file_bytes(path);
}

[[noreturn]] void no_clips(const std::filesystem::path& path) {
  throw Error("mesh " + quote(path.filename().string()) +
              " has no vertex animation (clips are read from MD2 and glTF files)");
}

std::string clip_names(const std::vector<ClipInfo>& clips) {
  std::string out;
  for (size_t i = 0; i < clips.size() && i < 20; ++i)
    out += (i ? ", " : "") + std::to_string(i) + " " + clips[i].name;
  return clips.size() > 20 ? out + ", ..." : out;
}

const ClipInfo& find_clip(const std::vector<ClipInfo>& clips, const ClipRef& ref,
                          const std::filesystem::path& path) {
  const std::string has = " (" + quote(path.filename().string()) + " has " +
                          std::to_string(clips.size()) + " clips: " + clip_names(clips) + ")";
  if (ref.name.empty()) {
    if (ref.index < 0 || ref.index >= static_cast<int>(clips.size()))
      throw Error("no clip " + std::to_string(ref.index) + has);
    return clips[static_cast<size_t>(ref.index)];
  }
  for (const ClipInfo& c : clips)
    if (c.name == ref.name) return c;
  throw Error("no clip " + quote(ref.name) + has);
}

/// A glTF morph animation: its own key times, from ref.start_s.
VertexClip load_morph_clip(const std::filesystem::path& path, const ClipRef& ref,
                           const Mat4& source_transform) {
  const std::vector<MorphClip> clips = morph_clips(path);
  if (clips.empty()) no_clips(path);
  const std::vector<ClipInfo> infos = infos_of(clips);
  const ClipInfo& info = find_clip(infos, ref, path);
  const MorphClip* found = &clips[static_cast<size_t>(&info - infos.data())];
  VertexClip clip;
  clip.name = found->name;
  clip.source_fps = ref.fps;
  Mesh frame = load_mesh_file(path);
  for (size_t k = 0; k < found->times_s.size(); ++k) {
    frame.positions = found->positions[k];
    transform_mesh(frame, source_transform);
    clip.times_s.push_back(ref.start_s + found->times_s[k]);
    clip.positions.push_back(frame.positions);
  }
  return clip;
}

}  // namespace

std::vector<ClipInfo> list_vertex_clips(const std::filesystem::path& path) {
  if (is_gltf(path)) return infos_of(morph_clips(path));
  if (!is_md2(path)) return {};
  return clips_of(read_md2(path, file_bytes(path)).frame_names);
}

VertexClip load_vertex_clip(const std::filesystem::path& path, const ClipRef& ref,
                            const Mat4& source_transform) {
  if (!is_md2(path) && !is_gltf(path)) no_clips(path);
  if (!(ref.fps > 0.0) || !std::isfinite(ref.fps) || !std::isfinite(ref.start_s))
    throw Error("clip frame rate must be positive");
  if (is_gltf(path)) return load_morph_clip(path, ref, source_transform);
  const Md2Model model = read_md2(path, file_bytes(path));
  const std::vector<ClipInfo> clips = clips_of(model.frame_names);
  const ClipInfo& info = find_clip(clips, ref, path);
  VertexClip clip;
  clip.name = info.name;
  clip.source_fps = ref.fps;
  for (int k = 0; k < info.frame_count; ++k) {
    Mesh frame = model.rest;
    frame.positions = model.frames[static_cast<size_t>(info.first_frame + k)];
    transform_mesh(frame, source_transform);
    clip.times_s.push_back(ref.start_s + static_cast<double>(k) / ref.fps);
    clip.positions.push_back(std::move(frame.positions));
  }
  return clip;
}

}  // namespace penumbra
