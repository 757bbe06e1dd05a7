#include "pictures.hpp"

#include <algorithm>

#include "penumbra/io/image_io.hpp"
#include "penumbra/pipeline/outputs.hpp"

namespace penumbra::viewer {

namespace {

constexpr const char* kNames[] = {"beauty", "visibility", "error", "signed_error", "split"};

/// Left half of a, right half of b, a light divider between.
report::Rgb8Image split_picture(const report::Rgb8Image& a, const report::Rgb8Image& b) {
  report::Rgb8Image out = a;
  const int half = a.width() / 2;
  for (int y = 0; y < a.height(); ++y)
    for (int x = half; x < a.width(); ++x)
      out(x, y) = x == half ? std::array<uint8_t, 3>{230, 230, 230} : b(x, y);
  return out;
}

bool same_frame(const RenderOutput& a, const RenderOutput& b) {
  return a.job.generation == b.job.generation && a.error.empty() && b.error.empty() &&
         a.job.camera.width == b.job.camera.width && a.job.camera.height == b.job.camera.height;
}

}  // namespace

const char* to_string(ViewMode mode) {
  return kNames[static_cast<int>(mode)];
}

std::optional<ViewMode> parse_view_mode(const std::string& name) {
  for (int i = 0; i < static_cast<int>(std::size(kNames)); ++i)
    if (name == kNames[i]) return static_cast<ViewMode>(i);
  return std::nullopt;
}

report::Rgb8Image visibility_picture(const Image<float>& v) {
  report::Rgb8Image out(v.width(), v.height());
  for (size_t i = 0; i < v.size(); ++i) {
    const uint8_t g = linear_to_srgb8(v[i]);
    out[i] = {g, g, g};
  }
  return out;
}

report::Rgb8Image make_picture(ViewMode mode, int light, const RenderOutput& shown,
                               const RenderOutput* reference, PictureInfo& info) {
  info = {};
  const MethodResult& result = shown.results.front();
  const size_t l = std::min<size_t>(static_cast<size_t>(light), result.per_light.size() - 1);
  const bool have_reference = reference && same_frame(shown, *reference);
  if (have_reference)
    info.error = compare_results(*shown.frame, reference->results.front(), result);
  switch (mode) {
    case ViewMode::beauty:
      return shown.beauty.front();
    case ViewMode::split:
      return shown.beauty.size() > 1 ? split_picture(shown.beauty[0], shown.beauty[1])
                                     : shown.beauty.front();
    case ViewMode::visibility:
      return visibility_picture(result.per_light[l].lit);
    case ViewMode::error:
    case ViewMode::signed_error:
      break;
  }
  if (!have_reference) {
    info.waiting_for_reference = true;
    return visibility_picture(result.per_light[l].lit);
  }
  const Image<float>& v = result.per_light[l].lit;
  const Image<float>& ref = reference->results.front().per_light[l].lit;
  Image<float> signed_error(v.width(), v.height());
  for (size_t i = 0; i < v.size(); ++i) signed_error[i] = v[i] - ref[i];
  const Image<float> mask = surface_mask(shown.frame->gbuffer());
  info.error_scale = report::common_error_scale({&signed_error}, mask);
  return mode == ViewMode::error
             ? report::abs_error_picture(signed_error, mask, info.error_scale)
             : report::signed_error_picture(signed_error, mask, info.error_scale);
}

}  // namespace penumbra::viewer
