// Error sweeps of `ssm` (Atty 2006, §4.2, Figs. 17–20) and `silhouette_map` soft against
// `pcss` at equal cost (Valient 2005 §2.2.1). Prints CSV, writes SVG line plots.
//   scripts/build.sh release --target sweep_ssm
//   ./build/release/bench/sweep_ssm [--size N] [--out docs/images] [--skip-cost]
// Metric: the paper's, mean |V − V_exact| over the pixels exact shadows or puts in penumbra
// (ErrorStats::mean_abs_shadowed), over the receiver (the ground, mesh 0): `ssm` computes no
// self-shadowing (§3.1), and the paper measures the soft shadow map. `all_px` is the same metric
// over every surface pixel (compare_results), occluder self-shadowing included.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "penumbra/core/math.hpp"
#include "penumbra/metrics/error_metrics.hpp"
#include "penumbra/pipeline/frame.hpp"
#include "penumbra/pipeline/outputs.hpp"
#include "penumbra/render/receivers.hpp"
#include "penumbra/report/svg_plot.hpp"
#include "penumbra/scene/builtin_scenes.hpp"
#include "penumbra/scene/model_paths.hpp"
#include "penumbra/scene/shapes.hpp"

namespace penumbra {
namespace {

/// One curve and one chart of a sweep, drawn by penumbra/report/svg_plot.hpp.
struct PlotSeries {
  std::string name;
  std::vector<double> x, y;
  bool dashed = false;
};
struct PlotSpec {
  std::string title, x_label, y_label;
  bool log2_x = false;
};
using Options = std::map<std::string, std::string>;

struct Setup {
  std::unique_ptr<Scene> scene;
  std::unique_ptr<Frame> frame;
  MethodResult exact;
  Image<float> ground;  // mask: active receiver pixels of mesh 0

  MethodResult run(const std::string& method, const Options& options = {}) const {
    const MethodInfo& info = MethodRegistry::builtin().get(method);
    return frame->run(info, resolve_options(info, options), false);
  }
};

Setup make_setup(Scene scene, int size) {
  Setup s;
  scene.camera.width = scene.camera.height = size;
  s.scene = std::make_unique<Scene>(std::move(scene));
  LightSampleSpec spec;
  spec.pattern = SamplePattern::grid;
  spec.k = 2;  // exact, ssm, pcss and silhouette_map ignore the samples
  s.frame = std::make_unique<Frame>(*s.scene, spec);
  s.exact = s.run("exact");
  const Image<uint8_t>& rc = s.frame->receivers(0);
  const GBuffer& g = s.frame->gbuffer();
  s.ground = Image<float>(rc.width(), rc.height(), 0.0f);
  for (size_t i = 0; i < rc.size(); ++i)
    s.ground.pixels()[i] = rc.pixels()[i] == kActive && g.mesh_id[i] == 0 ? 1.0f : 0.0f;
  return s;
}

struct Err {
  double ground = 0.0;       // paper's metric over the receiver
  double all = 0.0;          // paper's metric over every surface pixel
  double ground_mean = 0.0;  // mean |error| over every receiver pixel (lit ones too)
  size_t shadowed = 0;       // receiver pixels exact shadows or puts in penumbra
  double ms = 0.0;
};

Err measure(const Setup& s, const std::string& method, const Options& o) {
  const MethodResult r = s.run(method, o);
  Err e;
  const ErrorStats g = compare_images(s.exact.per_light[0].lit, r.per_light[0].lit, &s.ground);
  e.ground = g.mean_abs_shadowed;
  e.ground_mean = g.mean_abs;
  e.shadowed = g.shadowed_pixels;
  e.all = compare_results(*s.frame, s.exact, r).mean_abs_shadowed;
  e.ms = r.total_ms;
  return e;
}

/// The quad scene with its occluder turned by `deg` about the vertical axis (as in test_ssm):
/// edges cross the occluder-map texels.
Scene rotated_quad(double deg) {
  Scene s = make_builtin_scene("quad");
  const double c = std::cos(deg * kPi / 180.0), sn = std::sin(deg * kPi / 180.0);
  const float h = 0.5f * kQuadScene.occluder_side;
  Mesh m = make_quad(Vec3(0, kQuadScene.occluder_height, 0),
                     Vec3(static_cast<float>(2 * h * sn), 0, static_cast<float>(2 * h * c)),
                     Vec3(static_cast<float>(2 * h * c), 0, static_cast<float>(-2 * h * sn)));
  m.name = s.meshes[1].name;
  m.material = s.meshes[1].material;
  s.meshes[1] = std::move(m);
  return s;
}

/// The bunny scene, model moved by `d` (the light stays), light sides scaled by `light_scale`.
Scene bunny_variant(const Vec3& d, float light_scale) {
  Scene s = make_builtin_scene("bunny");
  for (Vec3& p : s.meshes[1].positions) p = p + d;
  s.lights[0].edge_u = s.lights[0].edge_u * light_scale;
  s.lights[0].edge_v = s.lights[0].edge_v * light_scale;
  return s;
}

const char* kPass[2] = {"one-pass", "two-pass"};
Options pass_opts(int two, Options o = {}) {
  o["two_pass"] = two ? "true" : "false";
  return o;
}

std::string out_dir = "docs/images";

void plot(const std::string& file, const PlotSpec& spec, const std::vector<PlotSeries>& series) {
  plot::Chart chart;
  chart.title = spec.title;
  chart.x = {spec.x_label, spec.log2_x ? plot::Scale::log2 : plot::Scale::linear};
  chart.y = {spec.y_label, plot::Scale::linear};
  std::vector<plot::Series> lines;
  for (const PlotSeries& ps : series) {
    plot::Series l;
    l.name = ps.name;
    l.x = ps.x;
    l.y = ps.y;
    l.dashed = ps.dashed;
    lines.push_back(std::move(l));
  }
  plot::write_text_file(out_dir + "/" + file, plot::line_plot_svg(chart, lines));
  std::printf("# wrote %s/%s\n", out_dir.c_str(), file.c_str());
}

/// Fig. 17: occluder-map resolution.
void sweep_resolution(int size, bool have_bunny) {
  std::printf("\n# fig17: error vs occluder-map resolution (ssm_resolution 256, %d^2)\n", size);
  std::printf("scene,resolution,pass,err_ground,err_all_px,ms\n");
  std::vector<std::pair<std::string, Scene>> scenes;
  scenes.emplace_back("quad", make_builtin_scene("quad"));
  scenes.emplace_back("quad30", rotated_quad(30.0));
  if (have_bunny) scenes.emplace_back("bunny", make_builtin_scene("bunny"));
  std::vector<PlotSeries> series;
  for (auto& [name, scene] : scenes) {
    const Setup s = make_setup(std::move(scene), size);
    for (int two = 0; two < 2; ++two) {
      PlotSeries ps{name + " " + kPass[two], {}, {}, two == 0};
      for (int res : {32, 64, 128, 256, 512}) {
        const Err e = measure(s, "ssm", pass_opts(two, {{"resolution", std::to_string(res)}}));
        std::printf("%s,%d,%s,%.5f,%.5f,%.1f\n", name.c_str(), res, kPass[two], e.ground, e.all,
                    e.ms);
        ps.x.push_back(res);
        ps.y.push_back(e.ground);
      }
      series.push_back(std::move(ps));
    }
  }
  // The quads' errors are ~100× below the bunny's: their own plot.
  std::vector<PlotSeries> quads;
  for (const PlotSeries& ps : series)
    if (ps.name.rfind("quad", 0) == 0) quads.push_back(ps);
  plot("ssm_error_vs_resolution_quad.svg",
       {"ssm on quad / quad turned 30 deg: error vs occluder-map resolution",
        "occluder map side (texels)", "mean |V - V_exact| (shadowed px)", true},
       quads);
  plot("ssm_error_vs_resolution.svg",
       {"ssm: error vs occluder-map resolution (Fig. 17)", "occluder map side (texels)",
        "mean |V - V_exact| (shadowed px)", true},
       series);
}

/// Fig. 18: light size; Figs. 19–20: occluder position. All on the bunny.
void sweep_bunny(int size) {
  struct Case {
    double x;
    Vec3 d;
    float scale;
  };
  struct Sweep {
    const char* id;
    const char* file;
    PlotSpec spec;
    std::vector<Case> cases;
  };
  std::vector<Sweep> sweeps;
  {
    Sweep w{"fig18_light_size",
            "ssm_error_vs_light_size.svg",
            {"ssm on bunny: error vs light size (Fig. 18)", "light side (x 0.5 = scene default)",
             "mean |V - V_exact| (shadowed px)", false},
            {}};
    for (double k : {0.5, 1.0, 1.5, 2.0, 2.5, 3.0})
      w.cases.push_back({k, Vec3(0.0f), static_cast<float>(k)});
    sweeps.push_back(std::move(w));
  }
  {
    Sweep w{"fig19_vertical",
            "ssm_error_vs_height.svg",
            {"ssm on bunny: error vs occluder height (Fig. 19)", "bunny lifted by (world units)",
             "mean |V - V_exact| (shadowed px)", false},
            {}};
    for (double h : {0.0, 0.1, 0.2, 0.3, 0.4, 0.5})
      w.cases.push_back({h, Vec3(0.0f, static_cast<float>(h), 0.0f), 1.0f});
    sweeps.push_back(std::move(w));
  }
  {
    Sweep w{"fig20_lateral",
            "ssm_error_vs_lateral.svg",
            {"ssm on bunny: error vs lateral offset (Fig. 20)",
             "bunny moved along x (world units, light fixed)", "mean |V - V_exact| (shadowed px)",
             false},
            {}};
    for (double x : {0.0, 0.25, 0.5, 0.75, 1.0})
      w.cases.push_back({x, Vec3(static_cast<float>(x), 0.0f, 0.0f), 1.0f});
    sweeps.push_back(std::move(w));
  }
  for (const Sweep& w : sweeps) {
    std::printf("\n# %s (bunny, %d^2, resolution 128, ssm_resolution 256)\n", w.id, size);
    std::printf("x,pass,err_ground,err_all_px,mean_abs_ground,shadowed_px,ms\n");
    PlotSeries one{"one-pass", {}, {}, true}, two{"two-pass", {}, {}, false};
    PlotSeries one_m{"one-pass", {}, {}, true}, two_m{"two-pass", {}, {}, false};
    for (const Case& c : w.cases) {
      const Setup s = make_setup(bunny_variant(c.d, c.scale), size);
      for (int t = 0; t < 2; ++t) {
        const Err e = measure(s, "ssm", pass_opts(t));
        std::printf("%.2f,%s,%.5f,%.5f,%.5f,%zu,%.1f\n", c.x, kPass[t], e.ground, e.all,
                    e.ground_mean, e.shadowed, e.ms);
        (t ? two : one).x.push_back(c.x);
        (t ? two : one).y.push_back(e.ground);
        (t ? two_m : one_m).x.push_back(c.x);
        (t ? two_m : one_m).y.push_back(e.ground_mean);
      }
    }
    plot(w.file, w.spec, {one, two});
    // The same error summed over a fixed pixel set (mean over every receiver pixel): the
    // per-shadowed-pixel metric is diluted when the penumbra (the denominator) grows.
    PlotSpec m = w.spec;
    m.title += ", all receiver px";
    m.y_label = "mean |V - V_exact| (every receiver px)";
    const std::string f = w.file;
    plot(f.substr(0, f.size() - 4) + "_all_receiver.svg", m, {one_m, two_m});
  }
}

/// Best of three method times (ms) and the last result's error.
Err timed(const Setup& s, const std::string& method, const Options& o) {
  Err best = measure(s, method, o);
  for (int i = 0; i < 2; ++i) best.ms = std::min(best.ms, s.run(method, o).total_ms);
  return best;
}

/// silhouette_map soft vs pcss at equal cost, small spherical light (r = 0.1) at the scene
/// light's centre: the pcss setting whose time is closest to silhouette_map's.
void equal_cost(int size, bool have_bunny) {
  std::printf("\n# equal cost: silhouette_map soft vs pcss, sphere light r 0.1, %d^2\n", size);
  std::printf("scene,method,settings,err_all_px,ms\n");
  std::vector<std::string> names = {"spheres"};
  if (have_bunny) names.push_back("bunny");
  for (const std::string& name : names) {
    Scene scene = make_builtin_scene(name);
    Light& l = scene.lights[0];
    l.shape = LightShape::sphere;
    l.radius = 0.1f;
    const Setup s = make_setup(std::move(scene), size);
    for (int res : {512, 1024, 2048}) {
      const std::string r = std::to_string(res);
      const Err sm = timed(s, "silhouette_map", {{"mode", "soft"}, {"resolution", r}});
      std::printf("%s,silhouette_map,soft res=%d,%.5f,%.1f\n", name.c_str(), res, sm.all, sm.ms);
      Err best;
      std::string best_set;
      double best_gap = 1e300;
      for (int p : {4, 8, 12, 16, 24, 32, 48, 64}) {
        const Options o = {{"resolution", r},
                           {"pcf_samples", std::to_string(p)},
                           {"blocker_samples", std::to_string(std::max(6, p / 2))}};
        const Err e = timed(s, "pcss", o);
        char set[96];
        std::snprintf(set, sizeof set, "res=%d pcf=%d blocker=%d", res, p, std::max(6, p / 2));
        std::printf("%s,pcss,%s,%.5f,%.1f\n", name.c_str(), set, e.all, e.ms);
        const double gap = std::abs(std::log(e.ms / sm.ms));
        if (gap < best_gap) best_gap = gap, best = e, best_set = set;
        if (e.ms > 2.0 * sm.ms) break;
      }
      std::printf(
          "%s,EQUAL-COST,silhouette_map soft res=%d (%.1f ms) vs pcss %s (%.1f ms),"
          "%.5f vs %.5f,\n",
          name.c_str(), res, sm.ms, best_set.c_str(), best.ms, sm.all, best.all);
    }
  }
}

}  // namespace
}  // namespace penumbra

int main(int argc, char** argv) {
  using namespace penumbra;
  int size = 256;
  bool cost = true;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--size" && i + 1 < argc)
      size = std::atoi(argv[++i]);
    else if (a == "--out" && i + 1 < argc)
      out_dir = argv[++i];
    else if (a == "--skip-cost")
      cost = false;
    else {
      std::fprintf(stderr, "usage: sweep_ssm [--size N] [--out DIR] [--skip-cost]\n");
      return 2;
    }
  }
  const bool have_bunny = find_model("bunny00.off").has_value();
  if (!have_bunny)
    std::printf("# bunny00.off not found (run scripts/fetch-models.sh): bunny sweeps skipped\n");
  try {
    sweep_resolution(size, have_bunny);
    if (have_bunny) sweep_bunny(size);
    if (cost) equal_cost(2 * size, have_bunny);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "sweep_ssm: %s\n", e.what());
    return 1;
  }
  return 0;
}
