// Frame sequences of an animated scene: the frame range of `render --frames`, and a renderer that
// poses the scene frame after frame and runs every method on each pose, preparing the methods
// (and building the BVH) once when only lights and camera move, again on every frame, inside the
// methods' own times, when the geometry moves.
#pragma once

#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "penumbra/pipeline/frame.hpp"
#include "penumbra/scene/scene.hpp"

namespace penumbra {

/// Frame indices first, first + step, ... ≤ last of an Animation (frame i at frame_time(i)).
struct FrameRange {
  int first = 0;
  int last = 0;
  int step = 1;

  std::vector<int> frames() const;
};

/// Parses "START:END[:STEP]" (whole base-10 numbers, START ≤ END, STEP ≥ 1); throws Error naming
/// what is wrong.
FrameRange parse_frame_range(std::string_view text);

/// Throws Error unless `animation` animates something and holds every frame of `range`.
void check_frame_range(const FrameRange& range, const Animation& animation);

/// A method of the sequence: its registry entry and resolved options.
struct SequenceMethod {
  const MethodInfo* info = nullptr;
  MethodOptions options;
};

/// One rendered frame: its pose, the Frame built on it, and each method's result (in the order
/// the methods were given).
struct SequenceFrame {
  int index = 0;
  double time_s = 0.0;
  std::shared_ptr<const Scene> scene;
  std::unique_ptr<Frame> frame;
  std::vector<MethodResult> results;
};

class SequenceRenderer {
 public:
  /// `rest` is the animated scene (validated, camera sized); it must outlive the renderer.
  /// In a sequence whose geometry moves, `raytrace` with bvh=shared is run with bvh=rebuild:
  /// the frame's BVH is built outside every method's time, so tracing it would hide the
  /// rebuild a ray tracer pays per frame.
  SequenceRenderer(const Scene& rest, std::vector<SequenceMethod> methods,
                   const LightSampleSpec& samples, bool want_masks);

  /// Poses frame `index` of the animation and runs every method on it. Methods are prepared at
  /// the first frame, and again at every frame when the geometry moves: then prepare_ms (inside
  /// total_ms) is that frame's. Frames may come in any increasing order.
  SequenceFrame render(int index);

  const std::vector<SequenceMethod>& methods() const { return methods_; }

 private:
  const Scene& rest_;
  std::vector<SequenceMethod> methods_;
  std::vector<std::unique_ptr<ShadowMethod>> prepared_;
  LightSampleSpec samples_;
  bool want_masks_;
  bool moves_geometry_;
  // The pose the methods were prepared on (and the shared BVH built from, when the geometry is
  // still): kept alive while they compute.
  std::shared_ptr<const Scene> prepared_scene_;
  std::shared_ptr<const EmbreeScene> embree_;
};

/// Temporal error of one method at frame t against the reference: the mean, over the pixels that
/// are surface in both frames and every light, of |(V_t − V_{t−1}) − (E_t − E_{t−1})| — the
/// change between frames that the method adds (flicker, popping, crawling) and the reference has
/// not. 0 when no pixel counts.
double temporal_error(const MethodResult& previous, const MethodResult& current,
                      const MethodResult& reference_previous, const MethodResult& reference_current,
                      const GBuffer& gbuffer_previous, const GBuffer& gbuffer_current);

}  // namespace penumbra
