// What `penumbra render` writes for one method: beauty.png, the visibility image (EXR or PFM),
// stats.json and optional G-buffer AOVs.
#pragma once

#include <deque>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "penumbra/io/image_io.hpp"
#include "penumbra/metrics/error_metrics.hpp"
#include "penumbra/pipeline/frame.hpp"
#include "penumbra/pipeline/shading.hpp"

namespace penumbra {

enum class FloatFormat { exr, pfm };

/// Visibility layers: "light<l>" per light (V_coef), "light<l>.R/.G/.B" for textured lights, and
/// "mask" (1 = surface pixel, 0 = background) so that `compare` skips the background. The V_coef
/// layers view the result's own images (4 bytes a pixel not copied); `owned` holds the others.
struct VisibilityLayers {
  std::deque<Image<float>> owned;  // a deque: the views point into it as it grows
  std::vector<FloatLayerView> layers;
};
VisibilityLayers visibility_layers(const Frame& frame, const MethodResult& result);

/// Writes visibility.exr (all layers) or visibility.pfm (+ visibility_light<l>.pfm, mask.pfm).
void write_visibility(const std::filesystem::path& dir, const Frame& frame,
                      const MethodResult& result, FloatFormat format);

/// The AOV names write_aovs knows, in the order `--help` lists them.
const std::vector<std::string>& aov_names();

/// Writes the G-buffer layers named in `aovs` (position, normal, shading_normal, depth, uv,
/// mesh_id) as float images.
void write_aovs(const std::filesystem::path& dir, const GBuffer& gbuffer,
                const std::vector<std::string>& aovs, FloatFormat format);

/// Everything stats.json holds: method, parameters, scene, samples, times_ms (with "total"),
/// counters (per light when there are several), frame (the shared stages: embree_device_ms,
/// bvh_build_ms, gbuffer_ms, receivers_ms, irradiance_ms; `penumbra render` adds the rest of the
/// process: startup_ms, load_ms, setup_ms, aovs_ms, methods_ms, outputs_ms, other_ms and their sum
/// elapsed_ms) and, when given, the error against `exact`.
nlohmann::json stats_json(const Frame& frame, const MethodResult& result,
                          const ErrorStats* vs_exact);

/// Writes what one method's frame holds into `dir` (created if missing): beauty.png, the
/// visibility image, and when `exact` is given error_vs_exact.png (then `error` is set). Returns
/// stats.json's contents with "shading", not written: the caller adds its own keys.
nlohmann::json write_method_frame(const std::filesystem::path& dir, const Frame& frame,
                                  const MethodResult& result, const MethodResult* exact,
                                  ShadingMode shading, FloatFormat format,
                                  std::optional<ErrorStats>& error);

/// Error of `test` against `ref` over every light's surface pixels (pooled).
ErrorStats compare_results(const Frame& frame, const MethodResult& ref, const MethodResult& test);

/// |test − ref| of light 0, and the surface mask, for error-map pictures.
Image<float> result_difference(const MethodResult& ref, const MethodResult& test);
Image<float> surface_mask(const GBuffer& gbuffer);

}  // namespace penumbra
