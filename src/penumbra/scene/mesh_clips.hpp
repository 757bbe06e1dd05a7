// A mesh file's own animation as a VertexClip: the keyframes of an MD2 model (Quake II vertex
// animation), grouped into clips by frame name ("run1".."run6" is the clip "run"), or a glTF
// animation (morph targets, skins, node transforms: gltf_morph.hpp).
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "penumbra/scene/animation.hpp"
#include "penumbra/scene/mesh.hpp"

namespace penumbra {

/// Which clip of a file, and how to time a file whose frames carry no times (MD2).
struct ClipRef {
  std::string name;  // empty: by index
  int index = 0;
  double fps = 10.0;     // frames per second of the file's frame sequence (Quake II plays at 10)
  double start_s = 0.0;  // scene time of the clip's first frame
};

/// One clip of a file: its name and its frames' indices in the file.
struct ClipInfo {
  std::string name;
  int first_frame = 0;
  int frame_count = 0;
};

/// The clips of an animated mesh file, in file order (an empty list for a still format).
std::vector<ClipInfo> list_vertex_clips(const std::filesystem::path& path);

/// The clip's frames, each one keyframe of the mesh load_mesh_file reads from `path` (same vertex
/// count and order), placed by `source_transform` (the mesh's world = M × file). Times: frame k at
/// start_s + k / fps. Throws Error for a file without that clip (listing the clips it has).
VertexClip load_vertex_clip(const std::filesystem::path& path, const ClipRef& clip,
                            const Mat4& source_transform);

}  // namespace penumbra
