#include "penumbra/report/sequence_run.hpp"

#include <cmath>
#include <cstdio>
#include <optional>
#include <set>

#include "penumbra/core/error.hpp"
#include "penumbra/core/files.hpp"
#include "penumbra/pipeline/video.hpp"
#include "penumbra/report/sequence_page.hpp"
#include "penumbra/report/summary_table.hpp"

namespace penumbra {

namespace {

namespace fs = std::filesystem;

/// A method's figures summed over the sequence, for the summary table and frames.json.
struct MethodTotals {
  double ms = 0.0;
  int frames = 0;
  ErrorStats error_sum;  // field by field; max_abs is the maximum
  int error_frames = 0;
  double temporal_sum = 0.0;
  int temporal_frames = 0;

  void add_error(const ErrorStats& e) {
    error_sum.mean_abs_shadowed += e.mean_abs_shadowed;
    error_sum.mean_abs += e.mean_abs;
    error_sum.rmse += e.rmse;
    error_sum.max_abs = std::max(error_sum.max_abs, e.max_abs);
    error_sum.psnr += e.psnr;
    error_sum.frac_over_1_255 += e.frac_over_1_255;
    error_sum.frac_over_1_16 += e.frac_over_1_16;
    error_sum.pixels += e.pixels;
    error_sum.shadowed_pixels += e.shadowed_pixels;
    ++error_frames;
  }
  /// The per-frame errors' means (max_abs: the worst frame's).
  std::optional<ErrorStats> mean_error() const {
    if (error_frames == 0) return std::nullopt;
    const double n = error_frames;
    ErrorStats m = error_sum;
    m.mean_abs_shadowed /= n;
    m.mean_abs /= n;
    m.rmse /= n;
    m.psnr /= n;
    m.frac_over_1_255 /= n;
    m.frac_over_1_16 /= n;
    return m;
  }
  std::optional<double> mean_temporal() const {
    if (temporal_frames == 0) return std::nullopt;
    return temporal_sum / temporal_frames;
  }
};

int reference_index(const std::vector<SequenceMethod>& methods) {
  for (size_t m = 0; m < methods.size(); ++m)
    if (methods[m].info->name == "exact") return static_cast<int>(m);
  return -1;
}

/// frames.csv: one row per frame and method; the stage columns are every stage any method
/// reported, empty where a method has none.
std::string frames_csv(const nlohmann::json& entries) {
  std::set<std::string> stages;
  for (const nlohmann::json& e : entries)
    for (const auto& [stage, ms] : e["times_ms"].items())
      if (stage != "total") stages.insert(stage);
  static const char* kErrors[] = {"mean_abs", "mean_abs_shadowed", "rmse",          "max_abs",
                                  "psnr",     "frac_over_1_255",   "frac_over_1_16"};
  std::string csv = "frame,time_s,method,total_ms,prepare_ms";
  for (const std::string& s : stages) {
    csv += ",stage_";
    csv += s;
    csv += "_ms";
  }
  for (const char* k : kErrors) {
    csv += ',';
    csv += k;
  }
  csv += ",temporal_error\n";
  auto number = [](const nlohmann::json& j, const std::string& key) {
    if (!j.contains(key)) return std::string();
    char text[64];
    std::snprintf(text, sizeof text, "%.9g", j[key].get<double>());
    return std::string(text);
  };
  // Appended piece by piece (GCC 12 misreports "," + string as overlapping).
  auto cell = [&csv](const std::string& text) {
    csv += ',';
    csv += text;
  };
  for (const nlohmann::json& e : entries) {
    csv += std::to_string(e["frame"].get<int>());
    cell(number(e, "time_s"));
    cell(e["method"].get<std::string>());
    cell(number(e, "total_ms"));
    cell(number(e, "prepare_ms"));
    for (const std::string& s : stages) cell(number(e["times_ms"], s));
    const nlohmann::json none = nlohmann::json::object();
    const nlohmann::json& err = e.contains("error_vs_exact") ? e["error_vs_exact"] : none;
    for (const char* k : kErrors) cell(number(err, k));
    cell(number(e, "temporal_error"));
    csv += '\n';
  }
  return csv;
}

/// One frame's entry of frames.json for one method.
nlohmann::json frame_entry(const SequenceFrame& f, const MethodResult& r,
                           const nlohmann::json& stats, std::optional<double> temporal) {
  nlohmann::json e = {{"frame", f.index},           {"time_s", f.time_s},
                      {"method", r.method},         {"total_ms", r.total_ms},
                      {"prepare_ms", r.prepare_ms}, {"times_ms", stats["times_ms"]}};
  if (stats.contains("error_vs_exact")) e["error_vs_exact"] = stats["error_vs_exact"];
  if (temporal) e["temporal_error"] = *temporal;
  return e;
}

/// Writes every method's folder of frame `f`; adds its entries and totals.
void write_frame(const SequenceJob& job, const SequenceFrame& f, const SequenceFrame* previous,
                 int ref, std::vector<MethodTotals>& totals, nlohmann::json& entries) {
  const MethodResult* exact = ref >= 0 ? &f.results[ref] : nullptr;
  std::string line = "frame " + std::to_string(f.index);
  for (size_t m = 0; m < f.results.size(); ++m) {
    const MethodResult& r = f.results[m];
    std::optional<ErrorStats> error;
    nlohmann::json stats = write_method_frame(job.out / r.method / frame_folder(f.index), *f.frame,
                                              r, static_cast<int>(m) == ref ? nullptr : exact,
                                              job.shading, job.format, error);
    stats["backend"] = job.backend;
    stats["device"] = job.device;
    stats["sequence"] = {{"frame", f.index}, {"time_s", f.time_s}};
    std::optional<double> temporal;
    if (previous && exact)
      temporal = temporal_error(previous->results[m], r, previous->results[ref], *exact,
                                previous->frame->gbuffer(), f.frame->gbuffer());
    if (temporal) stats["temporal_error"] = *temporal;
    write_text_file(job.out / r.method / frame_folder(f.index) / "stats.json",
                    stats.dump(2) + "\n");
    entries.push_back(frame_entry(f, r, stats, temporal));
    MethodTotals& t = totals[m];
    t.ms += r.total_ms;
    ++t.frames;
    if (error) t.add_error(*error);
    if (temporal) {
      t.temporal_sum += *temporal;
      ++t.temporal_frames;
    }
    char part[96];
    std::snprintf(part, sizeof part, "%s %s %.1f ms", m == 0 ? ":" : ",", r.method.c_str(),
                  r.total_ms);
    line += part;
  }
  std::fprintf(stderr, "%s\n", line.c_str());
}

/// The summary block of frames.json, and the table rows (per-frame means).
std::vector<TableRow> summary_rows(const SequenceJob& job, const std::vector<MethodTotals>& totals,
                                   int ref, nlohmann::json& summary) {
  std::vector<TableRow> rows;
  for (size_t m = 0; m < job.methods.size(); ++m) {
    const MethodTotals& t = totals[m];
    const std::string& name = job.methods[m].info->name;
    TableRow row{name, t.frames > 0 ? t.ms / t.frames : 0.0, t.mean_error(),
                 "",   static_cast<int>(m) == ref,           t.mean_temporal()};
    nlohmann::json j = {{"frames", t.frames}, {"total_ms", t.ms}, {"mean_ms", row.ms}};
    if (row.vs_exact) j["mean_error_vs_exact"] = to_json(*row.vs_exact);
    if (row.temporal_error) j["mean_temporal_error"] = *row.temporal_error;
    summary[name] = j;
    rows.push_back(std::move(row));
  }
  return rows;
}

/// Whether the videos were written.
bool write_videos_if_possible(const SequenceJob& job, const std::vector<int>& frames, double fps) {
  const std::optional<fs::path> ffmpeg = find_executable("ffmpeg");
  if (!ffmpeg) {
    std::fprintf(stderr,
                 "note: ffmpeg not found: no beauty.mp4 or compare.mp4 (scripts/setup.sh "
                 "installs it)\n");
    return false;
  }
  std::vector<std::string> names;
  for (const SequenceMethod& m : job.methods) names.push_back(m.info->name);
  write_videos(*ffmpeg, job.out, names, frames, fps);
  std::fprintf(stderr, "videos: %s/<method>/beauty.mp4, %s/compare.mp4\n", job.out.c_str(),
               job.out.c_str());
  return true;
}

}  // namespace

void render_sequence(Scene& scene, const SequenceJob& job) {
  if (job.fps > 0.0) scene.animation.fps = job.fps;
  check_frame_range(job.range, scene.animation);
  const Animation& anim = scene.animation;
  const std::vector<int> frames = job.range.frames();
  std::fprintf(stderr, "sequence: frames %d..%d step %d (%zu frames at %g fps); moves%s%s%s\n",
               job.range.first, job.range.last, job.range.step, frames.size(), anim.fps,
               anim.moves_geometry() ? " geometry" : "", anim.moves_lights() ? " lights" : "",
               anim.moves_camera() ? " camera" : "");
  SequenceRenderer renderer(scene, job.methods, job.samples, job.shading == ShadingMode::integrate);
  const int ref = reference_index(job.methods);
  std::vector<MethodTotals> totals(job.methods.size());
  nlohmann::json entries = nlohmann::json::array();
  std::optional<SequenceFrame> previous;
  std::string header;
  int samples = 0;
  for (int index : frames) {
    SequenceFrame f = renderer.render(index);
    write_frame(job, f, previous ? &*previous : nullptr, ref, totals, entries);
    if (!previous) header = summary_header(*f.frame, std::string(to_string(job.shading)));
    samples = f.frame->samples().count();
    previous = std::move(f);
  }
  nlohmann::json summary = nlohmann::json::object();
  std::vector<TableRow> rows = summary_rows(job, totals, ref, summary);
  nlohmann::json methods_options = nlohmann::json::object();
  for (const SequenceMethod& m : renderer.methods())
    methods_options[m.info->name] = m.options.values();
  const nlohmann::json doc = {
      {"scene", scene.name},
      {"fps", anim.fps},
      {"range", {{"first", job.range.first}, {"last", job.range.last}, {"step", job.range.step}}},
      {"moves",
       {{"geometry", anim.moves_geometry()},
        {"lights", anim.moves_lights()},
        {"camera", anim.moves_camera()}}},
      {"reference", ref >= 0 ? nlohmann::json("exact") : nlohmann::json(nullptr)},
      {"parameters", methods_options},
      {"frames", entries},
      {"summary", summary}};
  write_text_file(job.out / "frames.json", doc.dump(2) + "\n");
  write_text_file(job.out / "frames.csv", frames_csv(entries));
  const std::string table =
      header + "\nSequence of " + std::to_string(frames.size()) +
      " frames: times and errors are per-frame means (max abs: the worst frame's); **temporal** "
      "= mean over frames t > first of the mean |(V_t − V_t−1) − (V_exact,t − V_exact,t−1)| over "
      "the surface pixels of both frames.\n\n" +
      format_table(rows, samples) + "\n" + table_column_key();
  std::printf("%s", table.c_str());
  write_text_file(job.out / "summary.md", table);
  const bool videos = write_videos_if_possible(job, frames, anim.fps);
  write_text_file(job.out / "index.html", sequence_page_html(doc, videos));
  std::fprintf(stderr, "report: %s\n", (job.out / "index.html").c_str());
}

}  // namespace penumbra
