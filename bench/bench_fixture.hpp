// The frame cache every benchmark shares: one frame per (scene, size, k, light scale), built once
// and reused by every iteration, so iterations time the method alone.
#pragma once

#include <benchmark/benchmark.h>

#include <functional>
#include <initializer_list>
#include <map>
#include <memory>
#include <optional>
#include <string>

#include "penumbra/pipeline/frame.hpp"
#include "penumbra/scene/builtin_scenes.hpp"
#include "penumbra/scene/model_paths.hpp"
#include "penumbra/shadows/registry.hpp"

namespace penumbra::bench {

struct Fixture {
  std::unique_ptr<Scene> scene;
  std::unique_ptr<Frame> frame;
};

/// False for a model scene whose model is not fetched (the benchmark then skips with a message).
inline bool scene_available(const std::string& scene) {
  if (scene == "bunny") return find_model("bunny00.off").has_value();
  if (scene == "dragon") return find_model("ChineseDragon-10kv.off").has_value();
  if (scene == "armadillo") return find_model("armadillo.off").has_value();
  if (scene == "elephant") return find_model("refined_elephant.off").has_value();
  return true;
}

inline constexpr const char* kNotFetched = "model not fetched: run scripts/fetch-models.sh";

/// The built-in `scene` at size×size with k×k grid samples, its lights' edges (and radii) scaled
/// by `light_scale` about their centres; nullptr when the scene's model is missing.
inline const Fixture* cached_frame(const std::string& scene, int size, int k,
                                   float light_scale = 1.0f) {
  static std::map<std::string, Fixture> cache;
  const std::string key = scene + "/" + std::to_string(size) + "/" + std::to_string(k) + "/" +
                          std::to_string(light_scale);
  auto it = cache.find(key);
  if (it == cache.end()) {
    if (!scene_available(scene)) return nullptr;
    Fixture f;
    f.scene = std::make_unique<Scene>(make_builtin_scene(scene));
    f.scene->camera.width = f.scene->camera.height = size;
    for (Light& l : f.scene->lights) {
      l.edge_u *= light_scale;
      l.edge_v *= light_scale;
      l.radius *= light_scale;
    }
    LightSampleSpec spec;
    spec.pattern = SamplePattern::grid;
    spec.k = k;
    f.frame = std::make_unique<Frame>(*f.scene, spec);
    it = cache.emplace(key, std::move(f)).first;
  }
  return &it->second;
}

/// Times `method` with `options` on frame `f`, one Frame::run per iteration (`before_each`, when
/// given, runs first inside the timed loop: e.g. a per-frame BVH rebuild). The listed counters of
/// the last iteration become benchmark counters. Returns the last iteration's first light (its
/// counters and stage times), or nothing when f is null: the benchmark is then skipped with
/// kNotFetched.
inline std::optional<Visibility> time_method(benchmark::State& state, const Fixture* f,
                                             const std::string& method,
                                             const std::map<std::string, std::string>& options,
                                             std::initializer_list<const char*> counters = {},
                                             const std::function<void()>& before_each = {}) {
  if (!f) {
    state.SkipWithError(kNotFetched);
    return std::nullopt;
  }
  const MethodInfo& info = MethodRegistry::builtin().get(method);
  const MethodOptions opts = resolve_options(info, options);
  std::optional<Visibility> last;
  for (auto _ : state) {
    if (before_each) before_each();
    MethodResult r = f->frame->run(info, opts, false);
    benchmark::DoNotOptimize(r.per_light[0].lit.data());
    last = std::move(r.per_light[0]);
  }
  if (last)
    for (const char* key : counters)
      if (last->counters.count(key)) state.counters[key] = last->counters.at(key);
  return last;
}

/// cached_frame for Args {size, k, light scale ×} at the given argument indices.
inline const Fixture* frame_of(const benchmark::State& state, const std::string& scene,
                               int size_arg = 0, int k_arg = 1, int light_scale_arg = 2) {
  return cached_frame(
      scene, static_cast<int>(state.range(size_arg)), static_cast<int>(state.range(k_arg)),
      light_scale_arg < 0 ? 1.0f : static_cast<float>(state.range(light_scale_arg)));
}

}  // namespace penumbra::bench
