// The videos of `render --frames`: each method's beauty frames as OUT/<method>/beauty.mp4 and all
// methods side by side as OUT/compare.mp4, encoded by the ffmpeg executable when it is installed.
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace penumbra {

/// The first executable `name` on $PATH, if any.
std::optional<std::filesystem::path> find_executable(const std::string& name);

/// Writes `out/<method>/beauty.mp4` for every method, from `out/<method>/frame_NNNN/beauty.png`
/// of `frames`, and `out/compare.mp4` (every method left to right, labelled with its name when
/// the DejaVu font is installed): H.264, yuv420p, `fps` frames a second. Each file is written to
/// a temporary and renamed; throws Error when ffmpeg fails, with its last line of diagnostics.
void write_videos(const std::filesystem::path& ffmpeg, const std::filesystem::path& out,
                  const std::vector<std::string>& methods, const std::vector<int>& frames,
                  double fps);

/// "frame_0042": the folder of frame 42 under OUT/<method>/.
std::string frame_folder(int frame);

}  // namespace penumbra
