// The page of an animated sequence: the summary with the temporal error, the per-frame plots, and
// the videos or, without ffmpeg, a flip-book of the frames.
#include <gtest/gtest.h>

#include <string>

#include "penumbra/report/sequence_page.hpp"

namespace penumbra {
namespace {

/// frames.json of a three-frame sequence of `exact` and `gears<x>` (a name to escape).
nlohmann::json three_frames() {
  nlohmann::json frames = nlohmann::json::array();
  for (int f = 4; f <= 8; f += 2) {
    frames.push_back({{"frame", f},
                      {"time_s", f / 24.0},
                      {"method", "exact"},
                      {"total_ms", 10.0 + f},
                      {"prepare_ms", 0.0}});
    nlohmann::json g = {
        {"frame", f},           {"time_s", f / 24.0},
        {"method", "gears<x>"}, {"total_ms", 2.0},
        {"prepare_ms", 0.0},    {"error_vs_exact", {{"mean_abs", 1e-3 * f}, {"max_abs", 0.5}}}};
    if (f > 4) g["temporal_error"] = 2e-4 * f;
    frames.push_back(g);
  }
  return {{"scene", "flag"},
          {"fps", 12.0},
          {"range", {{"first", 4}, {"last", 8}, {"step", 2}}},
          {"moves", {{"geometry", true}, {"lights", false}, {"camera", false}}},
          {"frames", frames},
          {"summary",
           {{"exact", {{"frames", 3}, {"mean_ms", 16.0}}},
            {"gears<x>",
             {{"frames", 3},
              {"mean_ms", 2.0},
              {"mean_error_vs_exact", {{"mean_abs", 6e-3}, {"max_abs", 0.5}}},
              {"mean_temporal_error", 1.4e-3}}}}}};
}

size_t count(const std::string& text, const std::string& what) {
  size_t n = 0;
  for (size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
  return n;
}

TEST(SequencePage, SummaryPlotsAndVideos) {
  const std::string html = sequence_page_html(three_frames(), true);
  EXPECT_NE(html.find("flag: frames 4–8 (step 2) at 12 fps"), std::string::npos);
  EXPECT_NE(html.find("Moving: geometry."), std::string::npos);
  // The summary: gears's mean time, error and temporal error; exact has none of the last two.
  EXPECT_NE(html.find("<td>gears&lt;x&gt;</td><td>3</td><td>2.0</td><td>6.000e-03</td><td>"
                      "5.000e-01</td><td>1.400e-03</td>"),
            std::string::npos);
  EXPECT_NE(html.find("<td>exact</td><td>3</td><td>16.0</td><td>–</td><td>–</td><td>–</td>"),
            std::string::npos);
  // Time (both methods), error and temporal error (gears only) per frame.
  EXPECT_EQ(count(html, "<svg"), 3u);
  EXPECT_EQ(count(html, "<video"), 3u);  // compare.mp4 and one per method
  EXPECT_NE(html.find("src=\"gears&lt;x&gt;/beauty.mp4\""), std::string::npos);
  EXPECT_EQ(html.find("<gears<x>"), std::string::npos);
}

TEST(SequencePage, FlipBookWithoutVideos) {
  const std::string html = sequence_page_html(three_frames(), false);
  EXPECT_EQ(count(html, "<video"), 0u);
  EXPECT_EQ(count(html, "class=flip"), 2u);
  EXPECT_NE(html.find("const frames = [\"frame_0004\",\"frame_0006\",\"frame_0008\"];"),
            std::string::npos);
  EXPECT_NE(html.find("exact/frame_0004/beauty.png"), std::string::npos);
  EXPECT_NE(html.find("}, 83);"), std::string::npos);  // 12 fps
}

}  // namespace
}  // namespace penumbra
