#include "penumbra/pipeline/outputs.hpp"

#include <tbb/parallel_invoke.h>

#include <algorithm>
#include <cmath>
#include <fstream>

#include "penumbra/core/error.hpp"
#include "penumbra/core/parallel.hpp"
#include "penumbra/core/simd.hpp"
#include "penumbra/metrics/error_map.hpp"

namespace penumbra {

Image<float> surface_mask(const GBuffer& g) {
  Image<float> mask(g.width, g.height, 0.0f);
  parallel_chunks(mask.size(), 1 << 16, [&](size_t begin, size_t end) {
    for (size_t i = begin; i < end; ++i) mask[i] = g.is_background(i) ? 0.0f : 1.0f;
  });
  return mask;
}

VisibilityLayers visibility_layers(const Frame& frame, const MethodResult& result) {
  VisibilityLayers out;
  for (size_t l = 0; l < result.per_light.size(); ++l) {
    const Visibility& vis = result.per_light[l];
    const std::string name = "light" + std::to_string(l);
    out.layers.push_back({name, &vis.lit});
    if (vis.lit_rgb) {
      const char* channels[3] = {".R", ".G", ".B"};
      for (int c = 0; c < 3; ++c) {
        Image<float>& img = out.owned.emplace_back(vis.lit.width(), vis.lit.height());
        for (size_t i = 0; i < img.size(); ++i) img[i] = (*vis.lit_rgb)[i][c];
        out.layers.push_back({name + channels[c], &img});
      }
    }
  }
  out.layers.push_back({"mask", &out.owned.emplace_back(surface_mask(frame.gbuffer()))});
  return out;
}

void write_visibility(const std::filesystem::path& dir, const Frame& frame,
                      const MethodResult& result, FloatFormat format) {
  if (format == FloatFormat::exr) {
    write_exr_views(dir / "visibility.exr", visibility_layers(frame, result).layers);
    return;
  }
  for (size_t l = 0; l < result.per_light.size(); ++l) {
    const Visibility& vis = result.per_light[l];
    const std::string file =
        l == 0 ? "visibility.pfm" : "visibility_light" + std::to_string(l) + ".pfm";
    if (vis.lit_rgb) {
      write_pfm(dir / file, *vis.lit_rgb);
    } else {
      write_pfm(dir / file, vis.lit);
    }
  }
  write_pfm(dir / "mask.pfm", surface_mask(frame.gbuffer()));
}

const std::vector<std::string>& aov_names() {
  static const std::vector<std::string> names = {"position", "normal", "shading_normal",
                                                 "depth",    "uv",     "mesh_id"};
  return names;
}

void write_aovs(const std::filesystem::path& dir, const GBuffer& g,
                const std::vector<std::string>& aovs, FloatFormat format) {
  const auto write_vec3 = [&](const std::string& name, const Image<Vec3>& img) {
    if (format == FloatFormat::pfm) return write_pfm(dir / (name + ".pfm"), img);
    std::vector<FloatLayer> layers;
    const char* channels[3] = {"X", "Y", "Z"};
    for (int c = 0; c < 3; ++c) {
      Image<float> ch(img.width(), img.height());
      for (size_t i = 0; i < img.size(); ++i) ch[i] = img[i][c];
      layers.push_back({channels[c], std::move(ch)});
    }
    write_exr(dir / (name + ".exr"), layers);
  };
  const auto write_scalar = [&](const std::string& name, const Image<float>& img) {
    if (format == FloatFormat::pfm) return write_pfm(dir / (name + ".pfm"), img);
    write_exr(dir / (name + ".exr"), {{"Y", img}});
  };
  for (const std::string& aov : aovs) {
    if (aov == "position") {
      write_vec3("position", g.world_pos);
    } else if (aov == "normal") {
      write_vec3("normal", g.geo_normal);
    } else if (aov == "shading_normal") {
      write_vec3("shading_normal", g.shading_normal);
    } else if (aov == "depth") {
      Image<float> depth = g.depth;  // background: 0 in the file (no infinities in outputs)
      for (size_t i = 0; i < depth.size(); ++i)
        if (g.is_background(i)) depth[i] = 0.0f;
      write_scalar("depth", depth);
    } else if (aov == "uv") {
      Image<Vec3> uv(g.width, g.height);
      for (size_t i = 0; i < uv.size(); ++i) uv[i] = Vec3(g.uv[i], 0.0f);
      write_vec3("uv", uv);
    } else if (aov == "mesh_id") {
      Image<float> ids(g.width, g.height);
      for (size_t i = 0; i < ids.size(); ++i) ids[i] = static_cast<float>(g.mesh_id[i]);
      write_scalar("mesh_id", ids);
    } else {
      std::string known;
      for (const std::string& name : aov_names()) known += (known.empty() ? "" : ", ") + name;
      throw Error("unknown AOV " + quote(aov) + " (known: " + known + ")");
    }
  }
}

namespace {

/// Counters as JSON numbers. JSON has no NaN or infinity (nlohmann writes them as null, which
/// reads back as "no value"): an undefined counter is left out and named in "undefined".
nlohmann::json counters_json(const Counters& counters) {
  nlohmann::json j = nlohmann::json::object();
  nlohmann::json undefined = nlohmann::json::array();
  for (const auto& [name, value] : counters) {
    if (std::isfinite(value))
      j[name] = value;
    else
      undefined.push_back(name);
  }
  if (!undefined.empty()) j["undefined"] = undefined;
  return j;
}

}  // namespace

nlohmann::json stats_json(const Frame& frame, const MethodResult& result,
                          const ErrorStats* vs_exact) {
  const Scene& scene = frame.scene();
  nlohmann::json j;
  j["method"] = result.method;
  j["simd"] = simd::active_target();  // the instruction set the dispatched kernels ran on
  nlohmann::json params = nlohmann::json::object();
  for (const auto& [key, value] : result.options.values()) params[key] = value;
  j["parameters"] = params;
  const LightSampleSpec& spec = frame.samples().spec();
  j["samples"] = {{"pattern", std::string(to_string(spec.pattern))},
                  {"k", spec.k},
                  {"count", frame.samples().count()},
                  {"seed", spec.seed}};
  const Bounds3 b = scene.bounds();
  j["scene"] = {{"name", scene.name},
                {"triangles", scene.triangle_count()},
                {"meshes", scene.meshes.size()},
                {"lights", scene.lights.size()},
                {"width", scene.camera.width},
                {"height", scene.camera.height},
                {"bounds_min", {b.lo.x, b.lo.y, b.lo.z}},
                {"bounds_max", {b.hi.x, b.hi.y, b.hi.z}}};
  nlohmann::json times = nlohmann::json::object();
  Counters counters;
  nlohmann::json lights = nlohmann::json::array();
  for (const Visibility& vis : result.per_light) {
    for (const auto& [stage, ms] : vis.times.stages()) times[stage] = times.value(stage, 0.0) + ms;
    for (const auto& [name, value] : vis.counters) counters[name] += value;
    nlohmann::json lt = nlohmann::json::object();
    for (const auto& [stage, ms] : vis.times.stages()) lt[stage] = ms;
    lights.push_back({{"times_ms", lt}, {"counters", counters_json(vis.counters)}});
  }
  times["total"] = result.total_ms;
  j["times_ms"] = times;
  j["counters"] = counters_json(counters);
  if (result.per_light.size() > 1) j["lights"] = lights;
  j["frame"] = {{"embree_device_ms", frame.embree().device_ms()},
                {"bvh_build_ms", frame.embree().build_ms()},
                {"gbuffer_ms", frame.gbuffer_ms()},
                {"receivers_ms", frame.receivers_ms()},
                {"irradiance_ms", frame.irradiance_ms()}};
  // Beside the methods (frame.hpp), so inside methods_ms: not a stage of its own.
  if (frame.irradiance_background_rows() > 0)
    j["frame"]["overlapped"] = {{"irradiance_background_ms", frame.irradiance_background_ms()},
                                {"irradiance_background_rows", frame.irradiance_background_rows()}};
  if (vs_exact) j["error_vs_exact"] = to_json(*vs_exact);
  return j;
}

namespace {

/// Stacks the light layers of a result vertically so all lights pool into one comparison.
Image<float> stacked(const MethodResult& r) {
  const int w = r.per_light.front().lit.width(), h = r.per_light.front().lit.height();
  Image<float> out(w, h * static_cast<int>(r.per_light.size()));
  for (size_t l = 0; l < r.per_light.size(); ++l)
    std::copy(r.per_light[l].lit.pixels().begin(), r.per_light[l].lit.pixels().end(),
              out.pixels().begin() + static_cast<long>(l * w * h));
  return out;
}

}  // namespace

ErrorStats compare_results(const Frame& frame, const MethodResult& ref, const MethodResult& test) {
  const Image<float> one = surface_mask(frame.gbuffer());
  Image<float> mask(one.width(), one.height() * static_cast<int>(ref.per_light.size()));
  for (size_t l = 0; l < ref.per_light.size(); ++l)
    std::copy(one.pixels().begin(), one.pixels().end(),
              mask.pixels().begin() + static_cast<long>(l * one.size()));
  return compare_images(stacked(ref), stacked(test), &mask);
}

Image<float> result_difference(const MethodResult& ref, const MethodResult& test) {
  return abs_difference(ref.per_light.front().lit, test.per_light.front().lit);
}

nlohmann::json write_method_frame(const std::filesystem::path& dir, const Frame& frame,
                                  const MethodResult& result, const MethodResult* exact,
                                  ShadingMode shading, FloatFormat format,
                                  std::optional<ErrorStats>& error) {
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec)
    throw Error("cannot create output folder " + quote(dir.string(), 200) + ": " + ec.message());
  error.reset();
  if (exact) {
    error = compare_results(frame, *exact, result);
    const Image<float> mask = surface_mask(frame.gbuffer());
    write_error_map_png(dir / "error_vs_exact.png", result_difference(*exact, result),
                        std::max(error->max_abs, 1.0 / 255.0), &mask);
  }
  std::vector<const Visibility*> per_light;
  for (const Visibility& v : result.per_light) per_light.push_back(&v);
  // The PNG encoder is serial and the EXR one mostly so: the two files are written side by
  // side, the beauty shaded beside the EXR too, a row at a time into the PNG's bytes.
  const RowShader beauty(frame, per_light, shading);
  tbb::parallel_invoke(
      [&] {
        write_png_rgb(dir / "beauty.png", frame.gbuffer().width, frame.gbuffer().height,
                      [&](int y, Vec3* out) { beauty.row(y, out); });
      },
      [&] { write_visibility(dir, frame, result, format); });
  nlohmann::json stats = stats_json(frame, result, error ? &*error : nullptr);
  stats["shading"] = std::string(to_string(shading));
  return stats;
}

}  // namespace penumbra
