// The picture each view shows, made from the workers' outputs with the report's colour scales.
#pragma once

#include <optional>
#include <string>

#include "penumbra/metrics/error_metrics.hpp"
#include "penumbra/report/report_images.hpp"
#include "render_worker.hpp"

namespace penumbra::viewer {

enum class ViewMode { beauty, visibility, error, signed_error, split };

const char* to_string(ViewMode mode);
std::optional<ViewMode> parse_view_mode(const std::string& name);
/// The error views compare against the reference (`exact`).
inline bool needs_reference(ViewMode mode) {
  return mode == ViewMode::error || mode == ViewMode::signed_error;
}

/// What the panel says about the picture shown.
struct PictureInfo {
  std::optional<ErrorStats> error;  // the method against the reference, all lights pooled
  double error_scale = 0.0;         // the error views' saturation value
  bool waiting_for_reference = false;
};

/// The picture of `mode` for light `light`: beauty (sRGB), visibility (V as sRGB grey), error
/// |V − V_ref| (viridis) or signed error V − V_ref (diverging), both on the report's scale
/// (common_error_scale), or split (the two methods' beauty, left and right halves). `reference`
/// is used when it renders the same generation at the same size; otherwise the error views show
/// the visibility and say they wait for it.
report::Rgb8Image make_picture(ViewMode mode, int light, const RenderOutput& shown,
                               const RenderOutput* reference, PictureInfo& info);

/// Linear V → the grey the visibility view shows.
report::Rgb8Image visibility_picture(const Image<float>& v);

}  // namespace penumbra::viewer
