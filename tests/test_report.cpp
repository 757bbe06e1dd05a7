// The comparison report: every method × scene has its images, rows and numbers (the same numbers
// as the pipeline computes directly), the common error scale, the penumbra window, the plots.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "penumbra/core/error.hpp"
#include "penumbra/pipeline/frame.hpp"
#include "penumbra/pipeline/outputs.hpp"
#include "penumbra/report/report.hpp"
#include "penumbra/report/report_images.hpp"
#include "penumbra/report/svg_plot.hpp"
#include "penumbra/scene/builtin_scenes.hpp"

namespace penumbra {
namespace {

namespace fs = std::filesystem;

std::string read_text(const fs::path& p) {
  std::ifstream f(p);
  std::stringstream s;
  s << f.rdbuf();
  return s.str();
}

/// `method` with its default options on `quad` at the report's 48×40, K×K grid samples: the
/// pipeline's own numbers, to check the report's against.
MethodResult quad_run(const std::string& method, int k, std::unique_ptr<Frame>& frame) {
  static const Scene quad = [] {
    Scene s = make_builtin_scene("quad");
    s.camera.width = 48;
    s.camera.height = 40;
    return s;
  }();
  LightSampleSpec samples;
  samples.k = k;
  frame = std::make_unique<Frame>(quad, samples);
  const MethodInfo& info = MethodRegistry::builtin().get(method);
  return frame->run(info, resolve_options(info, {}), false);
}

report::ReportSpec small_spec(const fs::path& out) {
  report::ReportSpec spec;
  spec.scenes = {"quad", "fence"};
  for (const char* name : {"exact", "raytrace", "pcss"}) {
    const MethodInfo& m = MethodRegistry::builtin().get(name);
    spec.methods.push_back(&m);
    spec.options.push_back(resolve_options(m, {}));
  }
  spec.size = std::make_pair(48, 40);
  spec.samples.k = 4;
  spec.sweeps = {"light_size"};
  spec.command_line = "test";
  spec.out_dir = out;
  return spec;
}

TEST(Report, EveryMethodAndSceneHasItsImagesRowsAndTheNumbersOfThePipeline) {
  const fs::path out = fs::temp_directory_path() / "penumbra_test_report";
  fs::remove_all(out);
  const fs::path index = report::write_report(small_spec(out));
  ASSERT_EQ(index, out / "index.html");
  const std::string html = read_text(index);
  const std::string md = read_text(out / "results.md");
  const nlohmann::json j = nlohmann::json::parse(read_text(out / "report.json"));
  ASSERT_EQ(j["scenes"].size(), 2u);
  EXPECT_NE(html.find("<svg"), std::string::npos);
  EXPECT_EQ(html.find("http://"), html.find("http://www.w3.org/2000/svg"));  // only the SVG ns
  EXPECT_EQ(html.find("https://"), std::string::npos);
  // The error-against-time chart also stands alone (scripts/results.sh copies it into docs/),
  // the same SVG as the page's, one series per method but the reference.
  const std::string chart = read_text(out / "error_vs_time.svg");
  EXPECT_EQ(chart.rfind("<svg xmlns='http://www.w3.org/2000/svg'", 0), 0u);
  EXPECT_NE(html.find(chart), std::string::npos);
  EXPECT_NE(chart.find("raytrace"), std::string::npos);
  EXPECT_NE(chart.find("pcss"), std::string::npos);

  for (const auto& scene : j["scenes"]) {
    const std::string name = scene["name"], folder = scene["folder"];
    EXPECT_NE(md.find("### " + name), std::string::npos);
    EXPECT_NE(html.find("id='scene-" + folder + "'"), std::string::npos);
    ASSERT_EQ(scene["methods"].size(), 3u);
    EXPECT_GE(scene["error_scale"].get<double>(), 1.0 / 255.0);
    EXPECT_LE(scene["error_scale"].get<double>(), 1.0);
    for (const auto& m : scene["methods"]) {
      const std::string method = m["method"];
      std::vector<std::string> images = {method, method + "_crop"};
      if (method != "exact") {
        images.insert(images.end(), {method + "_abs", method + "_signed", method + "_crop_abs"});
        EXPECT_TRUE(m.contains("error_vs_exact")) << name << " " << method;
        EXPECT_TRUE(m.contains("speed_vs_raytrace")) << name << " " << method;
        EXPECT_NE(md.find("| " + method + " | "), std::string::npos) << name << " " << method;
      }
      for (const std::string& img : images) {
        EXPECT_TRUE(fs::exists(out / folder / (img + ".png"))) << img;
        EXPECT_NE(html.find("src='" + folder + "/" + img + ".png'"), std::string::npos) << img;
      }
      EXPECT_GT(m["times_ms"]["total"].get<double>(), 0.0);
      EXPECT_TRUE(m.contains("frame"));
    }
    // The rays raytrace traces per pixel in each method's time [Wang 2014 Table 11]: its own 16
    // samples in its own time.
    const auto& rt = scene["methods"][1];
    ASSERT_EQ(rt["method"], "raytrace");
    EXPECT_DOUBLE_EQ(rt["equal_time_rays"].get<double>(), 16.0);
    const auto& pcss = scene["methods"][2];
    EXPECT_NEAR(
        pcss["equal_time_rays"].get<double>(),
        16.0 * pcss["times_ms"]["total"].get<double>() / rt["times_ms"]["total"].get<double>(),
        1e-6 * pcss["equal_time_rays"].get<double>());
  }
  // The report's numbers are the pipeline's: raytrace on quad, recomputed directly.
  std::unique_ptr<Frame> frame;
  const MethodResult e = quad_run("exact", 4, frame);
  const MethodResult r =
      frame->run(MethodRegistry::builtin().get("raytrace"),
                 resolve_options(MethodRegistry::builtin().get("raytrace"), {}), false);
  const ErrorStats direct = compare_results(*frame, e, r);
  const auto& reported = j["scenes"][0]["methods"][1]["error_vs_exact"];
  EXPECT_DOUBLE_EQ(reported["mean_abs_shadowed"].get<double>(), direct.mean_abs_shadowed);
  EXPECT_DOUBLE_EQ(reported["max_abs"].get<double>(), direct.max_abs);
  // 4×4 grid samples on the quad: the sampling error of 16 samples (measured 0.0415).
  EXPECT_NEAR(direct.mean_abs_shadowed, 0.0415, 0.004);

  ASSERT_EQ(j["sweeps"].size(), 1u);
  const auto& sweep = j["sweeps"][0];
  EXPECT_EQ(sweep["x"].size(), 4u);
  for (const char* m : {"raytrace", "pcss"})
    EXPECT_EQ(sweep["methods"][m]["mean_abs_shadowed"].size(), 4u) << m;
  EXPECT_NE(html.find("Sweep: light_size"), std::string::npos);
  fs::remove_all(out);
}

// Where `exact` is too slow (foliage, fragmented geometry), the reference is `raytrace` with more
// samples, on a frame of its own; every number is then against it, and `exact` is not run.
TEST(Report, RayTracedReferenceReplacesExact) {
  const fs::path out = fs::temp_directory_path() / "penumbra_test_report_rt";
  fs::remove_all(out);
  report::ReportSpec spec = small_spec(out);
  spec.scenes = {"quad"};
  spec.sweeps = {};
  spec.methods.erase(spec.methods.begin());  // no exact
  spec.options.erase(spec.options.begin());
  const MethodInfo& gears = MethodRegistry::builtin().get("gears");
  spec.methods.push_back(&gears);
  spec.options.push_back(resolve_options(gears, {}));
  spec.reference = "raytrace";
  spec.reference_k = 16;
  report::write_report(spec);
  const nlohmann::json j = nlohmann::json::parse(read_text(out / "report.json"));
  EXPECT_EQ(j["reference"], "raytrace 16×16");
  const auto& methods = j["scenes"][0]["methods"];
  ASSERT_EQ(methods.size(), 4u);  // the reference, raytrace, pcss, gears
  EXPECT_EQ(methods[0]["method"], "raytrace");
  EXPECT_EQ(methods[0]["samples"]["count"], 256);
  EXPECT_TRUE(fs::exists(out / "quad" / "raytrace_16x16.png"));
  for (size_t m = 1; m < methods.size(); ++m) {
    EXPECT_FALSE(methods[m].contains("error_vs_exact"));
    ASSERT_TRUE(methods[m].contains("error_vs_reference")) << methods[m]["method"];
  }
  // The numbers are the pipeline's: 4×4 gears against 16×16 raytrace, recomputed directly.
  std::unique_ptr<Frame> reference_frame, frame;
  const MethodResult ref = quad_run("raytrace", 16, reference_frame);
  const MethodResult g = quad_run("gears", 4, frame);
  const ErrorStats direct = compare_results(*frame, ref, g);
  EXPECT_DOUBLE_EQ(methods[3]["error_vs_reference"]["mean_abs_shadowed"].get<double>(),
                   direct.mean_abs_shadowed);
  // gears equals raytrace on the same samples, so both rows carry the same error (measured 0.0471:
  // 16 samples against 256).
  EXPECT_DOUBLE_EQ(methods[1]["error_vs_reference"]["mean_abs_shadowed"].get<double>(),
                   direct.mean_abs_shadowed);
  EXPECT_NEAR(direct.mean_abs_shadowed, 0.0471, 0.003);
  const std::string md = read_text(out / "results.md");
  EXPECT_NE(md.find("Errors are against `raytrace 16×16`"), std::string::npos);
  EXPECT_NE(md.find("| raytrace_16x16 | "), std::string::npos);
  EXPECT_NE(md.find("(reference)"), std::string::npos);

  spec.reference_k = 4;  // the methods' own samples: the sample-exact ones have no error at all
  report::write_report(spec);
  const nlohmann::json same = nlohmann::json::parse(read_text(out / "report.json"));
  for (int m : {1, 3})
    EXPECT_EQ(same["scenes"][0]["methods"][m]["error_vs_reference"]["max_abs"].get<double>(), 0.0);
  spec.reference = "path_trace";
  EXPECT_THROW(report::write_report(spec), Error);
  fs::remove_all(out);
}

TEST(Report, CommonErrorScaleIsTheRoundedMedianOfThePerMethod99thPercentiles) {
  const Image<float> mask(10, 10, 1.0f);
  Image<float> a(10, 10, 0.03f), b(10, 10, -0.3f), c(10, 10, 0.9f);
  EXPECT_DOUBLE_EQ(report::common_error_scale({&a, &b, &c}, mask), 0.5);  // median 0.3 -> 0.5
  EXPECT_DOUBLE_EQ(report::common_error_scale({&a, &c}, mask), 0.05);     // lower median 0.03
  const Image<float> zero(10, 10, 0.0f);
  EXPECT_DOUBLE_EQ(report::common_error_scale({&zero}, mask), 1.0 / 255.0);
  // Masked pixels do not count.
  Image<float> masked_out(10, 10, 0.0f);
  Image<float> big(10, 10, 0.0f);
  big(3, 3) = 0.8f;
  EXPECT_DOUBLE_EQ(report::common_error_scale({&big}, masked_out), 1.0 / 255.0);
  EXPECT_DOUBLE_EQ(report::common_error_scale({&big}, mask), 1.0);
}

TEST(Report, PenumbraWindowFindsThePenumbra) {
  Image<float> v(64, 64, 1.0f);
  const Image<float> mask(64, 64, 1.0f);
  for (int y = 40; y < 56; ++y)
    for (int x = 8; x < 24; ++x) v(x, y) = 0.5f;
  const report::CropRect r = report::penumbra_window(v, mask);
  EXPECT_EQ(r.size, 16);
  EXPECT_EQ(r.x, 8);
  EXPECT_EQ(r.y, 40);
  report::Rgb8Image pic(64, 64, {0, 0, 0});
  pic(8, 40) = {255, 0, 0};
  const report::Rgb8Image z = report::crop_zoom(pic, r, 3);
  EXPECT_EQ(z.width(), 48);
  EXPECT_EQ(z(2, 2)[0], 255);
  EXPECT_EQ(z(3, 3)[0], 0);
}

TEST(Report, PlotsLabelTicksReadablyAndSkipWhatALogAxisCannotShow) {
  EXPECT_EQ(plot::tick_label(150), "150");
  EXPECT_EQ(plot::tick_label(0.0039), "0.0039");
  EXPECT_EQ(plot::tick_label(0.5), "0.5");
  EXPECT_EQ(plot::tick_label(1e-7), "1e-07");
  plot::Chart c;
  c.x = {"ms", plot::Scale::log10};
  c.y = {"error", plot::Scale::log10};
  const std::string svg =
      plot::line_plot_svg(c, {{"a&b", {1, 10, 100}, {0.1, 0.0, 0.01}, false, true, {}, {}, ""}});
  EXPECT_NE(svg.find("a&amp;b"), std::string::npos);
  EXPECT_EQ(svg.find("nan"), std::string::npos);
  EXPECT_EQ(svg.find("inf"), std::string::npos);
  // Two usable points of three: two markers.
  size_t circles = 0;
  for (size_t p = svg.find("<circle"); p != std::string::npos; p = svg.find("<circle", p + 1))
    ++circles;
  EXPECT_EQ(circles, 2u);
  const std::string bars = plot::stacked_bars_svg("t", "ms", {{"m", {{"a", 2.0}, {"b", 3.0}}}});
  EXPECT_NE(bars.find(">5</text>"), std::string::npos);  // the total
}

}  // namespace
}  // namespace penumbra
