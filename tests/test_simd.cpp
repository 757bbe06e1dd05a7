// Runtime SIMD dispatch (core/simd.hpp): PENUMBRA_SIMD's names, and the sample-exact methods'
// masks bit for bit the same on every target this CPU runs (so the same as `raytrace` on each).
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>

#include "penumbra/core/error.hpp"
#include "penumbra/core/simd.hpp"
#include "penumbra/scene/model_paths.hpp"
#include "support/frame_helpers.hpp"
#include "support/mask_agreement.hpp"

namespace penumbra {
namespace {

using test::grid_samples;
using test::make_test_frame;
using test::TestFrame;

/// Restores the best target when a test ends, whatever it pinned.
struct Unpin {
  ~Unpin() { simd::pin(""); }
};

TEST(Simd, EveryAvailableTargetCanBePinnedAndIsReported) {
  const Unpin unpin;
  const std::vector<std::string> names = simd::available();
  ASSERT_FALSE(names.empty());
  EXPECT_EQ(names.back(), "scalar");  // best first; scalar runs everywhere
  const std::map<std::string, std::string> shown = {{"avx512", "AVX-512"},
                                                    {"avx2", "AVX2"},
                                                    {"sse4", "SSE4"},
                                                    {"neon", "NEON"},
                                                    {"scalar", "scalar"}};
  for (const std::string& name : names) {
    simd::pin(name);
    EXPECT_EQ(simd::active_target(), shown.at(name)) << name;
    EXPECT_FALSE(simd::embree_isa().empty() && name != "neon" && name != "scalar") << name;
  }
  simd::pin("");
  EXPECT_EQ(simd::active_target(), shown.at(names.front()));
  EXPECT_TRUE(simd::embree_isa().empty());
}

TEST(Simd, UnknownOrMissingTargetsAreOneLineErrors) {
  const Unpin unpin;
  EXPECT_THROW(simd::pin("avx1024"), Error);
  EXPECT_THROW(simd::pin("AVX2 "), Error);
  const std::vector<std::string> names = simd::available();
  for (const char* name : {"avx512", "avx2", "sse4", "scalar"})
    if (std::find(names.begin(), names.end(), name) == names.end()) {
      try {
        simd::pin(name);
        ADD_FAILURE() << name << " pinned on a CPU without it";
      } catch (const Error& e) {
        EXPECT_EQ(std::string(e.what()).find('\n'), std::string::npos);
        EXPECT_NE(std::string(e.what()).find("lacks"), std::string::npos) << e.what();
      }
    }
}

/// Bit-for-bit per-sample masks of one light.
size_t differing_words(const MethodResult& a, const MethodResult& b) {
  const SampleMasks& ma = *a.per_light[0].masks;
  const SampleMasks& mb = *b.per_light[0].masks;
  size_t differ = 0;
  for (size_t i = 0; i < size_t(ma.width()) * ma.height(); ++i)
    for (int w = 0; w < ma.words_per_pixel(); ++w) differ += ma.pixel(i)[w] != mb.pixel(i)[w];
  return differ;
}

struct Case {
  std::string what;
  TestFrame frame;
  std::map<std::string, std::string> options;
};

std::vector<Case> cases() {
  std::vector<Case> c;
  // Row spans (grid, k = 16 and 32), the per-sample path (stratified), alpha, a round light, the
  // LUT-free default scene with its fence, and gears's culls switched off.
  c.push_back({"spheres k16", make_test_frame("spheres", 48, 48, grid_samples(16)), {}});
  c.push_back({"spheres k32", make_test_frame("spheres", 32, 32, grid_samples(32)), {}});
  c.push_back({"spheres stratified",
               make_test_frame("spheres", 40, 40, test::sample_spec(SamplePattern::stratified, 8)),
               {}});
  c.push_back({"fence", make_test_frame("fence", 48, 48, grid_samples(16)), {}});
  c.push_back({"default", make_test_frame("default", 48, 48, grid_samples(8)), {}});
  c.push_back({"disk light",
               make_test_frame(test::round_light_scene(LightShape::disk), 40, 40, grid_samples(8)),
               {}});
  c.push_back({"spheres, culls off",
               make_test_frame("spheres", 40, 40, grid_samples(16)),
               {{"pixel_cull", "false"}, {"hidden_cull", "false"}, {"solid_cull", "false"}}});
  if (find_model("bunny00.off"))
    c.push_back({"bunny", make_test_frame("bunny", 48, 48, grid_samples(16)), {}});
  return c;
}

TEST(Simd, GearsMasksAreIdenticalOnEveryTarget) {
  const Unpin unpin;
  const std::vector<std::string> names = simd::available();
  for (const Case& c : cases()) {
    simd::pin(names.front());
    const MethodResult best = c.frame.run("gears", c.options, true);
    // The best target's masks equal raytrace's (as in the gears suite) ...
    test::expect_equal_masks(
        test::compare_masks(c.frame, c.frame.run("raytrace", {}, true), best, true), 50);
    // ... and every other target's equal the best one's, word for word.
    for (size_t t = 1; t < names.size(); ++t) {
      simd::pin(names[t]);
      const MethodResult other = c.frame.run("gears", c.options, true);
      EXPECT_EQ(differing_words(best, other), 0u) << c.what << ": " << names[t];
      EXPECT_EQ(best.per_light[0].lit.pixels(), other.per_light[0].lit.pixels())
          << c.what << ": " << names[t];
    }
    std::printf("%s: %zu targets agree\n", c.what.c_str(), names.size());
  }
}

}  // namespace
}  // namespace penumbra
