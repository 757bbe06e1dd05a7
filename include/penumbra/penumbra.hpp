// Penumbra's public C++ API: load (load_scene, scene_file.hpp) or build (Scene, validate_scene) a
// scene, render it with a shadow method, read the visibility (and the per-sample masks of the
// sample-exact methods), compare two results. The one header a program includes; docs/api.md walks
// through it with a complete example.
//
// Every function reports bad input by throwing penumbra::Error (a std::runtime_error) whose
// what() is the one-line message the CLI prints after "penumbra: error: ".
#pragma once

#include <cstdint>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "penumbra/core/error.hpp"
#include "penumbra/core/image.hpp"
#include "penumbra/metrics/error_metrics.hpp"
#include "penumbra/render/visibility.hpp"
#include "penumbra/scene/scene.hpp"
#include "penumbra/scene/scene_file.hpp"  // load_scene(name_or_path)
#include "penumbra/shadows/registry.hpp"

namespace penumbra {

/// The library's version, "major.minor.patch" (the CMake package's version).
const char* version();

/// The built-in scenes' names, in `penumbra list`'s order.
std::vector<std::string> builtin_scene_names();

/// Every shadow method, in presentation order: name, summary, paper, whether it is sample-exact,
/// and its options with types, ranges and defaults (MethodRegistry::builtin()).
const std::vector<MethodInfo>& methods();

/// What to render: one method on the scene's camera and every light, as `penumbra render` does.
struct RenderSettings {
  std::string method = "gears";
  int width = 0;  // image size in pixels, 1..16384; 0 × 0: the scene camera's
  int height = 0;
  int samples = 16;              // K: K×K light samples per pixel, 1..64 (1 = the light's centre)
  std::string pattern = "grid";  // grid, stratified, decorrelated, interleaved, halton, poisson
  uint64_t seed = 1;             // of the random patterns
  std::map<std::string, std::string> options;  // method options, key → value (`--set`)
  bool masks = false;           // keep the per-sample masks (sample-exact methods only)
  bool beauty = true;           // shade the beauty image
  std::string backend = "cpu";  // or "vulkan" (gears, shadow_map, pcss, shadow_volume)
};

/// What render() made.
struct RenderResult {
  std::string method;
  std::map<std::string, std::string> options;  // every option's value, defaults included
  /// One per light: `lit` (V in [0, 1], H×W), `lit_rgb` for textured lights, `masks` (when
  /// settings.masks and the method is sample-exact: bit s of a pixel set = sample s blocked),
  /// the method's stage times and counters.
  std::vector<Visibility> lights;
  Image<Vec3> beauty;         // linear RGB, V × unshadowed irradiance (eq. 4.3) + ambient
  Image<uint8_t> surface;     // 1 = surface pixel, 0 = background (masked out of compare())
  int samples_per_pixel = 0;  // K×K
  double method_ms = 0.0;     // the method's time, all lights, prepare_ms included (as `render`'s)
  double prepare_ms = 0.0;    // its prepare(), when this render ran it (0 when reused)
  /// The shared stages, milliseconds: embree_device_ms, bvh_build_ms (0 when the BVH was
  /// reused), gbuffer_ms, receivers_ms, irradiance_ms.
  std::map<std::string, double> frame_ms;
};

/// Keeps what a scene's geometry costs to prepare — the Embree BVH, every method's prepare() —
/// across renders: render() again after moving a light or the camera reuses it all; a change of
/// meshes, materials or textures is noticed (by their contents) and prepares them again.
/// Not thread-safe: one render at a time per Renderer.
class Renderer {
 public:
  Renderer();
  ~Renderer();
  Renderer(const Renderer&) = delete;
  Renderer& operator=(const Renderer&) = delete;

  /// Validates `scene` (validate_scene: a scene built in code gets the checks a file gets) and
  /// renders it. Throws Error for bad settings, options or scenes.
  RenderResult render(const Scene& scene, const RenderSettings& settings);

 private:
  struct State;
  std::unique_ptr<State> state_;
};

/// One render with nothing kept (Renderer().render(scene, settings)).
RenderResult render(const Scene& scene, const RenderSettings& settings);

/// The metrics of `penumbra compare` of `test` against `reference`, one per light: over the
/// surface pixels of `reference`'s frame, as the CLI counts those of the reference file's mask.
/// Throws Error when the two differ in size or number of lights.
std::vector<ErrorStats> compare(const RenderResult& reference, const RenderResult& test);

}  // namespace penumbra
