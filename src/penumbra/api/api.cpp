// The public facade (include/penumbra/penumbra.hpp) over the pipeline: what `penumbra render` does
// for one method, with its outputs kept in memory instead of written.
#include <chrono>
#include <cstdio>
#include <deque>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "penumbra/api/geometry_hash.hpp"
#include "penumbra/core/light_samples.hpp"
#include "penumbra/core/stats.hpp"
#include "penumbra/penumbra.hpp"
#include "penumbra/pipeline/frame.hpp"
#include "penumbra/pipeline/outputs.hpp"
#include "penumbra/pipeline/shading.hpp"
#include "penumbra/render/embree_scene.hpp"
#include "penumbra/scene/builtin_scenes.hpp"

#ifdef PENUMBRA_HAVE_VULKAN
#include "penumbra/gpu/backend.hpp"
#endif

namespace penumbra {

namespace {

/// The checks the CLI's options get, with the same one-line messages (named after the setting).
void check_settings(const RenderSettings& s) {
  const bool sized = s.width != 0 || s.height != 0;
  if (sized && (s.width < 1 || s.height < 1 || s.width > 16384 || s.height > 16384))
    throw Error("size: expected WxH with 1..16384 pixels each, got " + std::to_string(s.width) +
                "x" + std::to_string(s.height));
  if (s.samples < 1 || s.samples > 64)
    throw Error("samples: expected K in 1..64 (K×K light samples), got " +
                std::to_string(s.samples));
  if (!parse_sample_pattern(s.pattern))
    throw Error("pattern: unknown light-sample pattern " + quote(s.pattern));
  if (s.backend != "cpu" && s.backend != "vulkan")
    throw Error("backend: expected cpu or vulkan, got " + quote(s.backend));
}

/// The key a prepared method is kept under: backend, name and every option's canonical value.
std::string method_key(const std::string& backend, const MethodInfo& info,
                       const MethodOptions& options) {
  std::string key = backend + "/" + info.name;
  for (const auto& [name, value] : options.values()) key += "/" + name + "=" + value;
  return key;
}

Image<uint8_t> surface_of(const GBuffer& g) {
  Image<uint8_t> surface(g.width, g.height, 0);
  for (size_t i = 0; i < g.pixel_count(); ++i) surface[i] = g.is_background(i) ? 0 : 1;
  return surface;
}

}  // namespace

const char* version() {
  return PENUMBRA_VERSION;
}

std::vector<std::string> builtin_scene_names() {
  std::vector<std::string> names;
  for (const BuiltinSceneInfo& info : builtin_scenes()) names.push_back(info.name);
  return names;
}

const std::vector<MethodInfo>& methods() {
  return MethodRegistry::builtin().methods();
}

/// Members are destroyed in reverse order: the prepared methods before the scene they point into
/// and the Vulkan device they run on.
struct Renderer::State {
#ifdef PENUMBRA_HAVE_VULKAN
  std::unique_ptr<gpu::Backend> vulkan;
  std::deque<MethodInfo> vulkan_methods;  // bound to `vulkan`; a deque keeps their addresses
#endif
  Scene prepared_scene;  // the geometry the BVH and the prepared methods were built from
  uint64_t geometry = 0;
  bool have_scene = false;
  std::shared_ptr<const EmbreeScene> embree;
  std::map<std::string, std::unique_ptr<ShadowMethod>> prepared;

  /// `info` itself on the CPU; its Vulkan twin (the device opened on first use) otherwise.
  const MethodInfo& bind(const MethodInfo& info, const std::string& backend) {
    if (backend == "cpu") return info;
#ifdef PENUMBRA_HAVE_VULKAN
    if (!gpu::Backend::supports(info.name)) {
      std::string list;
      for (const std::string& n : gpu::Backend::methods()) list += (list.empty() ? "" : ", ") + n;
      throw Error("backend vulkan: method '" + info.name + "' has no Vulkan implementation (" +
                  list + " have one)");
    }
    if (!vulkan) vulkan = std::make_unique<gpu::Backend>();
    for (const MethodInfo& bound : vulkan_methods)
      if (bound.name == info.name) return bound;
    return vulkan_methods.emplace_back(vulkan->vulkan_method(info));
#else
    throw Error(
        "backend vulkan: this build has no Vulkan backend (install libvulkan-dev and glslc, then "
        "rebuild)");
#endif
  }
};

Renderer::Renderer() : state_(std::make_unique<State>()) {}
Renderer::~Renderer() = default;

RenderResult Renderer::render(const Scene& scene, const RenderSettings& settings) {
  check_settings(settings);
  const MethodInfo& info = MethodRegistry::builtin().get(settings.method);
  const MethodOptions options = resolve_options(info, settings.options);
  State& st = *state_;
  const MethodInfo& bound = st.bind(info, settings.backend);

  // The frame's own copy, validated (a scene built in code gets a file's checks); its geometry
  // decides whether the BVH and the prepared methods still serve.
  Scene frame_scene = scene;
  if (settings.width > 0) {
    frame_scene.camera.width = settings.width;
    frame_scene.camera.height = settings.height;
  }
  validate_scene(frame_scene);
  const uint64_t geometry = geometry_hash(frame_scene);
  RenderResult out;
  if (!st.have_scene || geometry != st.geometry) {
    st.prepared.clear();
    st.embree.reset();
    st.prepared_scene = frame_scene;
    st.geometry = geometry;
    st.have_scene = true;
    st.embree = std::make_shared<const EmbreeScene>(st.prepared_scene);
    out.frame_ms["embree_device_ms"] = st.embree->device_ms();
    out.frame_ms["bvh_build_ms"] = st.embree->build_ms();
  } else {
    out.frame_ms["embree_device_ms"] = 0.0;
    out.frame_ms["bvh_build_ms"] = 0.0;
  }
  const std::string key = method_key(settings.backend, info, options);
  auto it = st.prepared.find(key);
  if (it == st.prepared.end()) {
    std::unique_ptr<ShadowMethod> method = bound.create(options);
    const auto start = std::chrono::steady_clock::now();
    method->prepare(st.prepared_scene);
    out.prepare_ms = elapsed_ms(start);
    it = st.prepared.emplace(key, std::move(method)).first;
  }

  LightSampleSpec spec;
  spec.pattern = *parse_sample_pattern(settings.pattern);
  spec.k = settings.samples;
  spec.seed = settings.seed;
  const Frame frame(frame_scene, spec, st.embree);
  MethodResult result = frame.run(bound, *it->second, options, settings.masks);
  out.method = result.method;
  out.options = result.options.values();
  out.method_ms = result.total_ms + out.prepare_ms;  // as Frame::run's one-shot total
  out.samples_per_pixel = frame.samples().count();
  out.frame_ms["gbuffer_ms"] = frame.gbuffer_ms();
  out.frame_ms["receivers_ms"] = frame.receivers_ms();
  if (settings.beauty) {
    std::vector<const Visibility*> per_light;
    for (const Visibility& v : result.per_light) per_light.push_back(&v);
    out.beauty = shade(frame, per_light, ShadingMode::modulate);
  }
  out.frame_ms["irradiance_ms"] = frame.irradiance_ms();
  out.surface = surface_of(frame.gbuffer());
  out.lights = std::move(result.per_light);
  return out;
}

RenderResult render(const Scene& scene, const RenderSettings& settings) {
  return Renderer().render(scene, settings);
}

std::vector<ErrorStats> compare(const RenderResult& reference, const RenderResult& test) {
  if (reference.lights.size() != test.lights.size())
    throw Error("the results hold different numbers of lights (" +
                std::to_string(reference.lights.size()) + " vs " +
                std::to_string(test.lights.size()) + ")");
  if (reference.surface.width() != test.surface.width() ||
      reference.surface.height() != test.surface.height())
    throw Error(
        "cannot compare images of different sizes: " + std::to_string(reference.surface.width()) +
        "x" + std::to_string(reference.surface.height()) + " vs " +
        std::to_string(test.surface.width()) + "x" + std::to_string(test.surface.height()) +
        " (render both at the same size)");
  Image<float> mask(reference.surface.width(), reference.surface.height(), 0.0f);
  for (size_t i = 0; i < mask.size(); ++i) mask[i] = reference.surface[i] ? 1.0f : 0.0f;
  std::vector<ErrorStats> out;
  for (size_t l = 0; l < reference.lights.size(); ++l)
    out.push_back(compare_images(reference.lights[l].lit, test.lights[l].lit, &mask));
  return out;
}

}  // namespace penumbra
