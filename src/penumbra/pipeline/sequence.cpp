#include "penumbra/pipeline/sequence.hpp"

#include <charconv>
#include <chrono>
#include <cmath>
#include <map>

#include "penumbra/core/error.hpp"
#include "penumbra/core/stats.hpp"

namespace penumbra {

std::vector<int> FrameRange::frames() const {
  std::vector<int> out;
  for (int f = first; f <= last; f += step) out.push_back(f);
  return out;
}

namespace {

/// A whole base-10 number ≥ 0 (no sign, blank or other base), or throws.
int parse_index(std::string_view part, std::string_view text, const char* what) {
  int value = 0;
  const char* end = part.data() + part.size();
  const auto [ptr, ec] = std::from_chars(part.data(), end, value);
  if (part.empty() || part.front() == '-' || part.front() == '+' || ec != std::errc() || ptr != end)
    throw Error("--frames " + quote(std::string(text)) + ": " + what +
                " must be a whole number (--frames START:END[:STEP], frame indices)");
  return value;
}

}  // namespace

FrameRange parse_frame_range(std::string_view text) {
  std::vector<std::string_view> parts;
  for (size_t begin = 0;;) {
    const size_t colon = text.find(':', begin);
    parts.push_back(text.substr(begin, colon == std::string_view::npos ? colon : colon - begin));
    if (colon == std::string_view::npos) break;
    begin = colon + 1;
  }
  if (parts.size() < 2 || parts.size() > 3)
    throw Error("--frames " + quote(std::string(text)) +
                ": expected START:END or START:END:STEP (frame indices)");
  FrameRange range;
  range.first = parse_index(parts[0], text, "START");
  range.last = parse_index(parts[1], text, "END");
  if (parts.size() == 3) {
    if (!parts[2].empty() && parts[2].front() == '-')
      throw Error("--frames " + quote(std::string(text)) + ": STEP must be at least 1");
    range.step = parse_index(parts[2], text, "STEP");
    if (range.step < 1)
      throw Error("--frames " + quote(std::string(text)) + ": STEP must be at least 1");
  }
  if (range.last < range.first)
    throw Error("--frames " + quote(std::string(text)) + ": END is before START");
  return range;
}

void check_frame_range(const FrameRange& range, const Animation& animation) {
  if (animation.empty())
    throw Error("--frames: the scene is still (it has no animation); render it without --frames");
  const int count = animation.frame_count();
  if (range.last >= count)
    throw Error("--frames " + std::to_string(range.first) + ":" + std::to_string(range.last) +
                ": the animation has frames 0.." + std::to_string(count - 1) + " (" +
                std::to_string(animation.start_s) + " s to " + std::to_string(animation.end_s) +
                " s at " + std::to_string(animation.fps) + " fps)");
}

SequenceRenderer::SequenceRenderer(const Scene& rest, std::vector<SequenceMethod> methods,
                                   const LightSampleSpec& samples, bool want_masks)
    : rest_(rest),
      methods_(std::move(methods)),
      samples_(samples),
      want_masks_(want_masks),
      moves_geometry_(rest.animation.moves_geometry()) {
  for (SequenceMethod& m : methods_) {
    const auto& values = m.options.values();
    const auto bvh = values.find("bvh");
    if (moves_geometry_ && m.info->name == "raytrace" && bvh != values.end() &&
        bvh->second == "shared") {
      std::map<std::string, std::string> overrides(values.begin(), values.end());
      overrides["bvh"] = "rebuild";
      m.options = resolve_options(*m.info, overrides);
    }
  }
}

SequenceFrame SequenceRenderer::render(int index) {
  SequenceFrame out;
  out.index = index;
  out.time_s = rest_.animation.frame_time(index);
  out.scene = std::make_shared<const Scene>(pose_scene(rest_, out.time_s));
  const bool prepare = prepared_.empty() || moves_geometry_;
  // The pose the methods were prepared on stays alive until every one of them is prepared on the
  // new one: a prepare may read what it kept of the old pose (raytrace's BVH update does).
  std::shared_ptr<const Scene> previous_pose = prepared_scene_;
  if (prepare) prepared_scene_ = out.scene;
  if (moves_geometry_) {
    out.frame = std::make_unique<Frame>(*out.scene, samples_);  // its own BVH, a shared stage
  } else {
    // Lights and camera move alone: one BVH for every frame, built with the first.
    if (!embree_) embree_ = std::make_shared<const EmbreeScene>(*prepared_scene_);
    out.frame = std::make_unique<Frame>(*out.scene, samples_, embree_);
  }
  for (size_t m = 0; m < methods_.size(); ++m) {
    const SequenceMethod& method = methods_[m];
    if (prepared_.size() <= m) prepared_.push_back(method.info->create(method.options));
    double prepare_ms = 0.0;
    if (prepare) {
      const auto start = std::chrono::steady_clock::now();
      prepared_[m]->prepare(*prepared_scene_);
      prepare_ms = elapsed_ms(start);
    }
    MethodResult result = out.frame->run(*method.info, *prepared_[m], method.options, want_masks_);
    result.prepare_ms = prepare_ms;
    result.total_ms += prepare_ms;
    out.results.push_back(std::move(result));
  }
  return out;
}

double temporal_error(const MethodResult& previous, const MethodResult& current,
                      const MethodResult& reference_previous, const MethodResult& reference_current,
                      const GBuffer& gbuffer_previous, const GBuffer& gbuffer_current) {
  double sum = 0.0;
  size_t count = 0;
  for (size_t l = 0; l < current.per_light.size(); ++l) {
    const Image<float>& v0 = previous.per_light[l].lit;
    const Image<float>& v1 = current.per_light[l].lit;
    const Image<float>& e0 = reference_previous.per_light[l].lit;
    const Image<float>& e1 = reference_current.per_light[l].lit;
    for (size_t i = 0; i < v1.size(); ++i) {
      if (gbuffer_previous.is_background(i) || gbuffer_current.is_background(i)) continue;
      // In double: the differences of nearly equal V are what is measured.
      const double method_change = static_cast<double>(v1[i]) - v0[i];
      const double reference_change = static_cast<double>(e1[i]) - e0[i];
      sum += std::abs(method_change - reference_change);
      ++count;
    }
  }
  return count > 0 ? sum / static_cast<double>(count) : 0.0;
}

}  // namespace penumbra
