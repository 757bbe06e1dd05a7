// `penumbra render --frames START:END[:STEP]`: an animated scene's frames rendered by every method,
// OUT/<method>/frame_NNNN/ per frame, OUT/frames.json and frames.csv, the summary table with the
// temporal error, and the videos when ffmpeg is installed.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "penumbra/pipeline/outputs.hpp"
#include "penumbra/pipeline/sequence.hpp"

namespace penumbra {

struct SequenceJob {
  FrameRange range;
  double fps = 0.0;  // > 0: overrides the scene's frame rate
  std::vector<SequenceMethod> methods;
  LightSampleSpec samples;
  ShadingMode shading = ShadingMode::modulate;
  FloatFormat format = FloatFormat::exr;
  std::filesystem::path out;
  std::string backend = "cpu";
  std::string device = "cpu";
};

/// Renders the sequence of `scene` (loaded, sized; its animation's fps set from job.fps here).
/// Throws Error for a still scene or a range outside the animation before anything is rendered.
void render_sequence(Scene& scene, const SequenceJob& job);

}  // namespace penumbra
