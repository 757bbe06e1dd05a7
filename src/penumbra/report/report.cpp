#include "penumbra/report/report.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>

#include "penumbra/core/error.hpp"
#include "penumbra/core/progress.hpp"
#include "penumbra/pipeline/frame.hpp"
#include "penumbra/pipeline/outputs.hpp"
#include "penumbra/report/report_data.hpp"
#include "penumbra/report/summary_table.hpp"
#include "penumbra/report/svg_plot.hpp"
#include "penumbra/scene/scene_file.hpp"

namespace penumbra::report {

namespace fs = std::filesystem;

namespace {

/// One method's run on a frame: its result, or the Error it threw.
struct Run {
  std::string name;  // the method's name; the reference's file-safe label (e.g. raytrace_64x64)
  std::optional<MethodResult> result;
  std::string failure;
  std::shared_ptr<const Frame> own_frame;  // the reference's frame, when it has its own samples
};

/// The reference's file-safe name: `exact`, or `raytrace_KxK`.
std::string reference_name(const ReportSpec& spec) {
  if (spec.reference == "exact") return "exact";
  return "raytrace_" + std::to_string(spec.reference_k) + "x" + std::to_string(spec.reference_k);
}

std::string reference_label(const ReportSpec& spec) {
  return report::reference_label(spec.reference, spec.reference_k);
}

Run run_one(const Frame& frame, const MethodInfo& info, const MethodOptions& options,
            const std::string& name, const char* what) {
  Run r;
  r.name = name;
  char line[160];
  std::snprintf(line, sizeof line, "  %-10s %-16s", what, name.c_str());
  begin_status_line(line);
  try {
    r.result = frame.run(info, options, false);
    std::snprintf(line, sizeof line, "  %-10s %-16s %10.1f ms", what, name.c_str(),
                  r.result->total_ms);
    end_status_line(line);
  } catch (const Error& e) {
    r.failure = e.what();
    std::snprintf(line, sizeof line, "  %-10s %-16s failed: ", what, name.c_str());
    end_status_line(line + one_line(e.what()));
  }
  return r;
}

/// The reference first, then every method. `exact` is the first method; a `raytrace` reference
/// runs on a frame of its own: the same scene and camera with reference_k² light samples of the
/// same pattern and seed.
std::vector<Run> run_methods(const Frame& frame, const ReportSpec& spec, const char* what) {
  std::vector<Run> runs;
  if (spec.reference == "raytrace") {
    LightSampleSpec samples = frame.samples().spec();
    samples.k = spec.reference_k;
    auto own = std::make_shared<const Frame>(frame.scene(), samples, frame.embree_shared());
    const MethodInfo& raytrace = MethodRegistry::builtin().get("raytrace");
    runs.push_back(
        run_one(*own, raytrace, resolve_options(raytrace, {}), reference_name(spec), what));
    runs.back().own_frame = std::move(own);
  }
  for (size_t m = 0; m < spec.methods.size(); ++m)
    runs.push_back(run_one(frame, *spec.methods[m], spec.options[m], spec.methods[m]->name, what));
  if (!runs.front().result)
    throw Error("the report needs its reference `" + reference_label(spec) +
                "`, which failed: " + runs.front().failure);
  return runs;
}

Scene load_report_scene(const std::string& name, const ReportSpec& spec) {
  Scene s = load_scene(name);
  if (spec.size) {
    s.camera.width = spec.size->first;
    s.camera.height = spec.size->second;
  }
  return s;
}

/// A folder name for a scene: its name with anything but [A-Za-z0-9_-] replaced.
std::string folder_name(const std::string& name, const std::vector<SceneEntry>& taken) {
  std::string f;
  for (char c : name) f += std::isalnum(static_cast<unsigned char>(c)) || c == '-' ? c : '_';
  if (f.empty()) f = "scene";
  std::string unique = f;
  for (int i = 2; std::any_of(taken.begin(), taken.end(),
                              [&](const SceneEntry& s) { return s.folder == unique; });
       ++i)
    unique = f + "_" + std::to_string(i);
  return unique;
}

Image<float> signed_difference(const MethodResult& ref, const MethodResult& test) {
  const Image<float>& r = ref.per_light.front().lit;
  const Image<float>& t = test.per_light.front().lit;
  Image<float> d(r.width(), r.height());
  for (size_t i = 0; i < d.size(); ++i) d[i] = t[i] - r[i];
  return d;
}

SceneEntry render_scene(const std::string& name, const ReportSpec& spec,
                        const std::vector<SceneEntry>& done) {
  const Scene scene = load_report_scene(name, spec);
  SceneEntry entry;
  entry.name = scene.name;
  entry.folder = folder_name(scene.name, done);
  entry.reference = reference_label(spec);
  std::fprintf(stderr, "scene '%s': %zu triangles, %dx%d\n", scene.name.c_str(),
               scene.triangle_count(), scene.camera.width, scene.camera.height);
  const Frame frame(scene, spec.samples);
  const std::vector<Run> runs = run_methods(frame, spec, scene.name.c_str());
  const fs::path dir = spec.out_dir / entry.folder;
  fs::create_directories(dir);

  const GBuffer& g = frame.gbuffer();
  entry.width = g.width;
  entry.height = g.height;
  const Image<float> mask = surface_mask(g);
  const MethodResult& reference = *runs.front().result;

  std::vector<Image<float>> errors(runs.size());
  std::vector<const Image<float>*> error_ptrs;
  for (size_t m = 1; m < runs.size(); ++m) {
    if (!runs[m].result) continue;
    errors[m] = signed_difference(reference, *runs[m].result);
    error_ptrs.push_back(&errors[m]);
  }
  entry.error_scale =
      spec.error_scale > 0.0 ? spec.error_scale : common_error_scale(error_ptrs, mask);
  entry.crop = penumbra_window(reference.per_light.front().lit, mask);
  entry.crop_zoom = std::max(1, 200 / entry.crop.size);

  std::vector<TableRow> rows;
  for (size_t m = 0; m < runs.size(); ++m) {
    MethodEntry me;
    me.method = runs[m].name;
    if (!runs[m].result) {
      me.failure = runs[m].failure;
      rows.push_back({me.method, 0.0, std::nullopt, me.failure, false, std::nullopt});
      entry.methods.push_back(std::move(me));
      continue;
    }
    const MethodResult& r = *runs[m].result;
    me.ms = r.total_ms;
    if (m > 0) me.vs_exact = compare_results(frame, reference, r);
    const Frame& run_frame = runs[m].own_frame ? *runs[m].own_frame : frame;
    me.stats = stats_json(run_frame, r, me.vs_exact ? &*me.vs_exact : nullptr);
    if (spec.reference != "exact" && me.stats.contains("error_vs_exact")) {
      me.stats["error_vs_reference"] = me.stats["error_vs_exact"];
      me.stats.erase("error_vs_exact");
    }
    for (const auto& [stage, ms] : me.stats["times_ms"].items())
      if (stage != "total") me.stages.emplace_back(stage, ms.get<double>());
    if (entry.frame.is_null()) entry.frame = me.stats["frame"];

    std::vector<const Visibility*> per_light;
    for (const Visibility& v : r.per_light) per_light.push_back(&v);
    const Rgb8Image beauty = srgb_picture(shade(frame, per_light, ShadingMode::modulate));
    write_picture(dir / (me.method + ".png"), beauty);
    write_picture(dir / (me.method + "_crop.png"), crop_zoom(beauty, entry.crop, entry.crop_zoom));
    if (m > 0) {
      const Rgb8Image abs_map = abs_error_picture(errors[m], mask, entry.error_scale);
      write_picture(dir / (me.method + "_abs.png"), abs_map);
      write_picture(dir / (me.method + "_signed.png"),
                    signed_error_picture(errors[m], mask, entry.error_scale));
      write_picture(dir / (me.method + "_crop_abs.png"),
                    crop_zoom(abs_map, entry.crop, entry.crop_zoom));
    }
    plot::write_text_file(dir / (me.method + ".json"), me.stats.dump(2) + "\n");
    rows.push_back({me.method, me.ms, me.vs_exact, "", m == 0, std::nullopt});
    entry.methods.push_back(std::move(me));
  }
  entry.summary_header = summary_header(frame, "modulate");
  entry.results_md = format_summary(rows, frame, "modulate", entry.reference);
  return entry;
}

/// The scene with every light's size multiplied by `f` (centres kept).
Scene scaled_lights(Scene s, double f) {
  for (Light& l : s.lights) {
    l.edge_u *= static_cast<float>(f);
    l.edge_v *= static_cast<float>(f);
    l.radius *= static_cast<float>(f);
  }
  return s;
}

SweepEntry run_sweep(const std::string& sweep, const ReportSpec& spec) {
  const std::string& scene_name = spec.scenes.front();
  const Scene base = load_report_scene(scene_name, spec);
  SweepEntry entry;
  entry.name = sweep;
  entry.scene = base.name;
  std::vector<std::pair<Scene, LightSampleSpec>> points;
  if (sweep == "samples") {
    entry.x_label = "K (K×K light samples per pixel)";
    for (int k : {1, 2, 4, 8, 16, 32})
      if (k <= std::max(16, spec.samples.k)) entry.x.push_back(k);
    for (double k : entry.x) {
      LightSampleSpec s = spec.samples;
      s.k = static_cast<int>(k);
      points.emplace_back(base, s);
    }
  } else if (sweep == "light_size") {
    entry.x_label = "light size (× the scene's)";
    entry.x = {0.25, 0.5, 1.0, 2.0};
    for (double f : entry.x) points.emplace_back(scaled_lights(base, f), spec.samples);
  } else if (sweep == "resolution") {
    entry.x_label = "image width and height (pixels)";
    const int top = std::max(base.camera.width, base.camera.height);
    for (int s = 32; s <= top; s *= 2) entry.x.push_back(s);
    if (entry.x.size() > 4) entry.x.erase(entry.x.begin(), entry.x.end() - 4);
    for (double px : entry.x) {
      Scene s = base;
      const double aspect = static_cast<double>(base.camera.height) / base.camera.width;
      s.camera.width = static_cast<int>(px);
      s.camera.height = std::max(1, static_cast<int>(std::lround(px * aspect)));
      points.emplace_back(std::move(s), spec.samples);
    }
  } else {
    throw Error("--sweep: unknown sweep '" + sweep + "' (known: samples, light_size, resolution)");
  }
  // Every run but the reference (run_methods puts it first).
  const size_t first = spec.reference == "exact" ? 1 : 0;
  for (size_t m = first; m < spec.methods.size(); ++m)
    entry.curves.push_back({spec.methods[m]->name, {}, {}});
  for (size_t p = 0; p < points.size(); ++p) {
    const Frame frame(points[p].first, points[p].second);
    const std::string what = sweep + " " + plot::tick_label(entry.x[p]);
    const std::vector<Run> runs = run_methods(frame, spec, what.c_str());
    for (size_t m = 1; m < runs.size(); ++m) {
      SweepCurve& c = entry.curves[m - 1];
      const double nan = std::nan("");
      c.error.push_back(
          runs[m].result
              ? compare_results(frame, *runs[0].result, *runs[m].result).mean_abs_shadowed
              : nan);
      c.ms.push_back(runs[m].result ? runs[m].result->total_ms : nan);
    }
  }
  return entry;
}

}  // namespace

std::string reference_label(const std::string& reference, int k) {
  if (reference == "exact") return "exact";
  return reference + " " + std::to_string(k) + "×" + std::to_string(k);
}

const std::vector<std::string>& sweep_names() {
  static const std::vector<std::string> names = {"samples", "light_size", "resolution"};
  return names;
}

fs::path write_report(const ReportSpec& in) {
  ReportSpec spec = in;
  if (spec.scenes.empty()) throw Error("report: no scene given (--scene)");
  if (spec.reference != "exact" && spec.reference != "raytrace")
    throw Error("--reference: unknown reference '" + spec.reference + "' (known: exact, raytrace)");
  if (spec.reference == "raytrace" && (spec.reference_k < 1 || spec.reference_k > 64))
    throw Error("--reference-samples: must be 1 to 64");
  if (spec.reference == "exact" &&
      (spec.methods.empty() || spec.methods.front()->name != "exact")) {
    const MethodInfo& exact = MethodRegistry::builtin().get("exact");
    spec.methods.insert(spec.methods.begin(), &exact);
    spec.options.insert(spec.options.begin(), resolve_options(exact, {}));
  }
  for (const std::string& s : spec.sweeps)
    if (std::find(sweep_names().begin(), sweep_names().end(), s) == sweep_names().end())
      throw Error("--sweep: unknown sweep '" + s + "' (known: samples, light_size, resolution)");
  std::error_code ec;
  fs::create_directories(spec.out_dir, ec);
  if (ec) throw Error("cannot create output folder " + spec.out_dir.string() + ": " + ec.message());

  ReportData data;
  data.reference = reference_label(spec);
  data.machine = machine_info();
  data.command_line = spec.command_line;
  data.samples = std::to_string(spec.samples.k) + "×" + std::to_string(spec.samples.k) + " " +
                 std::string(to_string(spec.samples.pattern));
  for (const std::string& name : spec.scenes)
    data.scenes.push_back(render_scene(name, spec, data.scenes));
  for (const std::string& sweep : spec.sweeps) data.sweeps.push_back(run_sweep(sweep, spec));

  const fs::path index = spec.out_dir / "index.html";
  plot::write_text_file(index, report_html(data));
  plot::write_text_file(spec.out_dir / "report.json", report_json(data).dump(2) + "\n");
  plot::write_text_file(spec.out_dir / "results.md", report_markdown(data));
  plot::write_text_file(spec.out_dir / "error_vs_time.svg", error_vs_time_svg(data));
  return index;
}

}  // namespace penumbra::report
