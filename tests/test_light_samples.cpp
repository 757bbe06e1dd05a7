// Tests for LightSamples: every sample pattern's positions, determinism, range, stratification,
// per-pixel decorrelation [Forest 2008 §4.2.1], interleaving [Forest 2008 §4.2.2], Halton
// values and the Poisson-disk spacing.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <set>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "penumbra/core/error.hpp"
#include "penumbra/core/light_samples.hpp"

namespace penumbra {
namespace {

LightSampleSpec make_spec(SamplePattern pattern, int k, uint64_t seed = 1, int interleave_n = 4) {
  LightSampleSpec spec;
  spec.pattern = pattern;
  spec.k = k;
  spec.seed = seed;
  spec.interleave_n = interleave_n;
  return spec;
}

std::vector<Vec2> samples_at(const LightSamples& samples, int x, int y) {
  std::vector<Vec2> out(static_cast<size_t>(samples.count()));
  samples.pixel_samples(x, y, out);
  return out;
}

bool identical(const std::vector<Vec2>& a, const std::vector<Vec2>& b) {
  if (a.size() != b.size()) return false;
  for (size_t i = 0; i < a.size(); ++i)
    if (a[i].x != b[i].x || a[i].y != b[i].y) return false;
  return true;
}

/// (a - b) wrapped into [0, 1).
double wrap_diff(double a, double b) {
  const double d = a - b;
  return d - std::floor(d);
}

/// Distance between a and b on the unit circle (0 .. 0.5).
double circle_dist(double a, double b) {
  const double d = std::abs(wrap_diff(a, b));
  return std::min(d, 1.0 - d);
}

double torus_dist(const Vec2& a, const Vec2& b) {
  const double dx = circle_dist(a.x, b.x);
  const double dy = circle_dist(a.y, b.y);
  return std::sqrt(dx * dx + dy * dy);
}

double min_torus_dist(const std::vector<Vec2>& points) {
  double best = 2.0;
  for (size_t i = 0; i < points.size(); ++i)
    for (size_t j = i + 1; j < points.size(); ++j)
      best = std::min(best, torus_dist(points[i], points[j]));
  return best;
}

bool is_random(SamplePattern pattern) {
  return pattern != SamplePattern::grid && pattern != SamplePattern::halton;
}

/// Pearson correlation of two equally long series.
double correlation(const std::vector<double>& a, const std::vector<double>& b) {
  const double n = static_cast<double>(a.size());
  double ma = 0.0, mb = 0.0;
  for (size_t i = 0; i < a.size(); ++i) {
    ma += a[i];
    mb += b[i];
  }
  ma /= n;
  mb /= n;
  double sab = 0.0, saa = 0.0, sbb = 0.0;
  for (size_t i = 0; i < a.size(); ++i) {
    sab += (a[i] - ma) * (b[i] - mb);
    saa += (a[i] - ma) * (a[i] - ma);
    sbb += (b[i] - mb) * (b[i] - mb);
  }
  return sab / std::sqrt(saa * sbb);
}

TEST(LightSamples, PatternNamesRoundTrip) {
  const std::vector<std::string> expected = {"grid",        "stratified", "decorrelated",
                                             "interleaved", "halton",     "poisson"};
  ASSERT_EQ(all_sample_patterns().size(), expected.size());
  for (size_t i = 0; i < expected.size(); ++i) {
    const SamplePattern pattern = all_sample_patterns()[i];
    EXPECT_EQ(to_string(pattern), expected[i]);
    const auto parsed = parse_sample_pattern(expected[i]);
    ASSERT_TRUE(parsed.has_value()) << expected[i];
    EXPECT_EQ(*parsed, pattern);
  }
  EXPECT_FALSE(parse_sample_pattern("").has_value());
  EXPECT_FALSE(parse_sample_pattern("jittered").has_value());
  EXPECT_FALSE(parse_sample_pattern("grid ").has_value());
}

TEST(LightSamples, ConstructorRejectsBadSpecs) {
  for (SamplePattern pattern : all_sample_patterns()) {
    EXPECT_THROW(LightSamples(make_spec(pattern, 0)), Error) << to_string(pattern);
    EXPECT_THROW(LightSamples(make_spec(pattern, -3)), Error) << to_string(pattern);
    EXPECT_THROW(LightSamples(make_spec(pattern, 65)), Error) << to_string(pattern);
    EXPECT_THROW(LightSamples(make_spec(pattern, 4, 1, 0)), Error) << to_string(pattern);
    EXPECT_THROW(LightSamples(make_spec(pattern, 4, 1, -1)), Error) << to_string(pattern);
    EXPECT_NO_THROW(LightSamples(make_spec(pattern, 1)));
    EXPECT_NO_THROW(LightSamples(make_spec(pattern, 4, 1, 1)));
  }
  try {
    LightSamples bad(make_spec(SamplePattern::grid, 65));
    FAIL() << "k = 65 accepted";
  } catch (const Error& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find("65"), std::string::npos) << message;
    EXPECT_EQ(message.find('\n'), std::string::npos) << message;
  }
  try {
    LightSamples bad(make_spec(SamplePattern::interleaved, 4, 1, 0));
    FAIL() << "interleave_n = 0 accepted";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("interleave_n"), std::string::npos) << e.what();
  }
}

TEST(LightSamples, CountAndSpecAreReported) {
  const LightSamples samples(make_spec(SamplePattern::poisson, 5, 42, 3));
  EXPECT_EQ(samples.k(), 5);
  EXPECT_EQ(samples.count(), 25);
  EXPECT_EQ(samples.spec().seed, 42u);
  EXPECT_EQ(samples.spec().interleave_n, 3);
  EXPECT_EQ(samples.spec().pattern, SamplePattern::poisson);
}

TEST(LightSamples, PerPixelFlagAndSharedSamples) {
  for (SamplePattern pattern : all_sample_patterns()) {
    const LightSamples samples(make_spec(pattern, 3));
    const bool expect_per_pixel =
        pattern == SamplePattern::decorrelated || pattern == SamplePattern::interleaved;
    EXPECT_EQ(samples.per_pixel(), expect_per_pixel) << to_string(pattern);
    if (expect_per_pixel) {
      EXPECT_TRUE(samples.shared_samples().empty()) << to_string(pattern);
    } else {
      ASSERT_EQ(samples.shared_samples().size(), 9u) << to_string(pattern);
      // The shared positions are what every pixel gets.
      const auto shared = samples.shared_samples();
      for (const auto& [x, y] : {std::pair{0, 0}, std::pair{17, 3}, std::pair{1023, 767}}) {
        const auto px = samples_at(samples, x, y);
        EXPECT_TRUE(identical(px, std::vector<Vec2>(shared.begin(), shared.end())))
            << to_string(pattern) << " pixel " << x << "," << y;
      }
    }
  }
}

TEST(LightSamples, GridPositionsAreCellCentres) {
  const LightSamples samples(make_spec(SamplePattern::grid, 4));
  const auto p = samples_at(samples, 5, 9);
  ASSERT_EQ(p.size(), 16u);
  for (int i = 0; i < 16; ++i) {
    EXPECT_FLOAT_EQ(p[i].x, ((i % 4) + 0.5f) / 4.0f) << i;
    EXPECT_FLOAT_EQ(p[i].y, ((i / 4) + 0.5f) / 4.0f) << i;
  }
  // Spot values: row-major, u fastest.
  EXPECT_EQ(p[0], Vec2(0.125f, 0.125f));
  EXPECT_EQ(p[1], Vec2(0.375f, 0.125f));
  EXPECT_EQ(p[4], Vec2(0.125f, 0.375f));
  EXPECT_EQ(p[6], Vec2(0.625f, 0.375f));
  EXPECT_EQ(p[15], Vec2(0.875f, 0.875f));

  const LightSamples odd(make_spec(SamplePattern::grid, 3));
  const auto q = samples_at(odd, 0, 0);
  EXPECT_FLOAT_EQ(q[4].x, 0.5f);
  EXPECT_FLOAT_EQ(q[4].y, 0.5f);
  EXPECT_FLOAT_EQ(q[5].x, 2.5f / 3.0f);
  EXPECT_FLOAT_EQ(q[5].y, 0.5f);
  EXPECT_FLOAT_EQ(q[6].x, 0.5f / 3.0f);
  EXPECT_FLOAT_EQ(q[6].y, 2.5f / 3.0f);
}

TEST(LightSamples, GridK1IsLightCentre) {
  const LightSamples samples(make_spec(SamplePattern::grid, 1));
  ASSERT_EQ(samples.count(), 1);
  const auto p = samples_at(samples, 12, 34);
  EXPECT_EQ(p[0], Vec2(0.5f, 0.5f));
}

TEST(LightSamples, SameSpecGivesIdenticalSamples) {
  for (SamplePattern pattern : all_sample_patterns()) {
    const LightSamples a(make_spec(pattern, 8, 7));
    const LightSamples b(make_spec(pattern, 8, 7));
    for (const auto& [x, y] : {std::pair{0, 0}, std::pair{1, 0}, std::pair{0, 1},
                               std::pair{313, 271}, std::pair{4095, 4095}}) {
      EXPECT_TRUE(identical(samples_at(a, x, y), samples_at(b, x, y)))
          << to_string(pattern) << " pixel " << x << "," << y;
      // Asking twice (in any order) gives the same positions: no hidden state.
      EXPECT_TRUE(identical(samples_at(a, x, y), samples_at(a, x, y))) << to_string(pattern);
    }
  }
}

TEST(LightSamples, SeedChangesRandomPatternsOnly) {
  for (SamplePattern pattern : all_sample_patterns()) {
    const LightSamples a(make_spec(pattern, 8, 1));
    const LightSamples b(make_spec(pattern, 8, 2));
    for (const auto& [x, y] : {std::pair{0, 0}, std::pair{9, 4}}) {
      const bool same = identical(samples_at(a, x, y), samples_at(b, x, y));
      if (is_random(pattern))
        EXPECT_FALSE(same) << to_string(pattern) << " ignores the seed";
      else
        EXPECT_TRUE(same) << to_string(pattern) << " should not depend on the seed";
    }
  }
}

TEST(LightSamples, AllPositionsFiniteAndInUnitSquare) {
  for (SamplePattern pattern : all_sample_patterns()) {
    for (int k : {1, 2, 3, 7, 16, 64}) {
      for (uint64_t seed : {1ull, 0ull, 0xffffffffffffffffull}) {
        const LightSamples samples(make_spec(pattern, k, seed, 3));
        for (const auto& [x, y] :
             {std::pair{0, 0}, std::pair{1, 2}, std::pair{-5, -7}, std::pair{65535, 65535}}) {
          for (const Vec2& p : samples_at(samples, x, y)) {
            ASSERT_TRUE(std::isfinite(p.x) && std::isfinite(p.y)) << to_string(pattern);
            ASSERT_GE(p.x, 0.0f) << to_string(pattern) << " k=" << k;
            ASSERT_LT(p.x, 1.0f) << to_string(pattern) << " k=" << k;
            ASSERT_GE(p.y, 0.0f) << to_string(pattern) << " k=" << k;
            ASSERT_LT(p.y, 1.0f) << to_string(pattern) << " k=" << k;
          }
        }
      }
    }
  }
}

TEST(LightSamples, DecorrelatedStaysInUnitSquareOverManyPixels) {
  const LightSamples samples(make_spec(SamplePattern::decorrelated, 8, 3));
  std::vector<Vec2> p(static_cast<size_t>(samples.count()));
  for (int y = 0; y < 128; ++y) {
    for (int x = 0; x < 128; ++x) {
      samples.pixel_samples(x, y, p);
      for (const Vec2& s : p) {
        ASSERT_TRUE(s.x >= 0.0f && s.x < 1.0f && s.y >= 0.0f && s.y < 1.0f)
            << "pixel " << x << "," << y << " sample " << s.x << "," << s.y;
      }
    }
  }
}

/// Checks sample i lies in cell (i % k, i / k) and every cell holds exactly one sample.
void expect_one_per_cell(const std::vector<Vec2>& p, int k, const std::string& what) {
  ASSERT_EQ(p.size(), static_cast<size_t>(k * k)) << what;
  std::vector<int> hits(static_cast<size_t>(k * k), 0);
  for (int i = 0; i < k * k; ++i) {
    const int cu = static_cast<int>(std::floor(static_cast<double>(p[i].x) * k));
    const int cv = static_cast<int>(std::floor(static_cast<double>(p[i].y) * k));
    EXPECT_EQ(cu, i % k) << what << " sample " << i;
    EXPECT_EQ(cv, i / k) << what << " sample " << i;
    if (cu >= 0 && cu < k && cv >= 0 && cv < k) ++hits[static_cast<size_t>(cv * k + cu)];
  }
  for (int c = 0; c < k * k; ++c)
    EXPECT_EQ(hits[static_cast<size_t>(c)], 1) << what << " cell " << c;
}

TEST(LightSamples, StratifiedHasOneJitteredSamplePerCell) {
  for (int k : {1, 2, 5, 16, 64}) {
    for (uint64_t seed : {1ull, 99ull}) {
      const LightSamples samples(make_spec(SamplePattern::stratified, k, seed));
      const auto p = samples_at(samples, 3, 4);
      expect_one_per_cell(p, k, "stratified k=" + std::to_string(k));
      // Same for every pixel.
      EXPECT_TRUE(identical(p, samples_at(samples, 200, 100)));
    }
  }
  // Jittered, not the grid: most samples sit away from their cell centres.
  const int k = 16;
  const auto p = samples_at(LightSamples(make_spec(SamplePattern::stratified, k)), 0, 0);
  int off_centre = 0;
  double mean_offset_u = 0.0;
  for (int i = 0; i < k * k; ++i) {
    const double du = p[i].x * k - (i % k + 0.5);
    const double dv = p[i].y * k - (i / k + 0.5);
    if (std::abs(du) > 0.01 || std::abs(dv) > 0.01) ++off_centre;
    mean_offset_u += std::abs(du);
  }
  mean_offset_u /= k * k;
  EXPECT_GT(off_centre, k * k * 9 / 10);
  // |jitter - 0.5| of a uniform jitter has mean 0.25.
  EXPECT_NEAR(mean_offset_u, 0.25, 0.05);
}

TEST(LightSamples, DecorrelatedIsAToroidalShiftOfTheStratifiedBase) {
  const int k = 8;
  const LightSamples base(make_spec(SamplePattern::stratified, k, 5));
  const LightSamples samples(make_spec(SamplePattern::decorrelated, k, 5));
  const auto b = samples_at(base, 0, 0);
  std::set<std::pair<float, float>> distinct_shifts;
  for (int y = 0; y < 16; ++y) {
    for (int x = 0; x < 16; ++x) {
      const auto p = samples_at(samples, x, y);
      const double su = wrap_diff(p[0].x, b[0].x);
      const double sv = wrap_diff(p[0].y, b[0].y);
      distinct_shifts.insert({static_cast<float>(su), static_cast<float>(sv)});
      for (int i = 0; i < k * k; ++i) {
        // Every sample is moved by the same shift, modulo 1 ...
        EXPECT_LT(circle_dist(wrap_diff(p[i].x, b[i].x), su), 1e-5) << x << "," << y << " " << i;
        EXPECT_LT(circle_dist(wrap_diff(p[i].y, b[i].y), sv), 1e-5) << x << "," << y << " " << i;
        // ... so pairwise differences modulo 1 are those of the base pattern.
        const int j = (i * 7 + 3) % (k * k);
        EXPECT_LT(circle_dist(wrap_diff(p[i].x, p[j].x), wrap_diff(b[i].x, b[j].x)), 1e-5);
        EXPECT_LT(circle_dist(wrap_diff(p[i].y, p[j].y), wrap_diff(b[i].y, b[j].y)), 1e-5);
      }
    }
  }
  // Every pixel gets its own shift.
  EXPECT_EQ(distinct_shifts.size(), 256u);
}

TEST(LightSamples, DecorrelatedShiftsAreUniformAndUncorrelated) {
  const int size = 64;
  const int k = 4;
  const LightSamples base(make_spec(SamplePattern::stratified, k, 11));
  const LightSamples samples(make_spec(SamplePattern::decorrelated, k, 11));
  const Vec2 b0 = samples_at(base, 0, 0)[0];
  std::vector<double> su(size * size), sv(size * size);
  for (int y = 0; y < size; ++y) {
    for (int x = 0; x < size; ++x) {
      const Vec2 p0 = samples_at(samples, x, y)[0];
      su[static_cast<size_t>(y * size + x)] = wrap_diff(p0.x, b0.x);
      sv[static_cast<size_t>(y * size + x)] = wrap_diff(p0.y, b0.y);
    }
  }
  double mean_u = 0.0, mean_v = 0.0;
  for (size_t i = 0; i < su.size(); ++i) {
    mean_u += su[i];
    mean_v += sv[i];
  }
  mean_u /= static_cast<double>(su.size());
  mean_v /= static_cast<double>(sv.size());
  EXPECT_NEAR(mean_u, 0.5, 0.05);
  EXPECT_NEAR(mean_v, 0.5, 0.05);

  // Horizontal and vertical neighbours, and u against v of the same pixel.
  std::vector<double> hu_a, hu_b, hv_a, hv_b, vu_a, vu_b;
  for (int y = 0; y < size; ++y) {
    for (int x = 0; x < size; ++x) {
      const size_t i = static_cast<size_t>(y * size + x);
      if (x + 1 < size) {
        hu_a.push_back(su[i]);
        hu_b.push_back(su[i + 1]);
        hv_a.push_back(sv[i]);
        hv_b.push_back(sv[i + 1]);
      }
      if (y + 1 < size) {
        vu_a.push_back(su[i]);
        vu_b.push_back(su[i + size]);
      }
    }
  }
  EXPECT_LT(std::abs(correlation(hu_a, hu_b)), 0.1);
  EXPECT_LT(std::abs(correlation(hv_a, hv_b)), 0.1);
  EXPECT_LT(std::abs(correlation(vu_a, vu_b)), 0.1);
  EXPECT_LT(std::abs(correlation(su, sv)), 0.1);
}

TEST(LightSamples, InterleavedTilesNByNStratifiedPatterns) {
  const int n = 4;
  const int k = 6;
  const LightSamples samples(make_spec(SamplePattern::interleaved, k, 3, n));
  for (int y = 0; y < 2 * n; ++y) {
    for (int x = 0; x < 2 * n; ++x) {
      const auto p = samples_at(samples, x, y);
      EXPECT_TRUE(identical(p, samples_at(samples, x + n, y))) << x << "," << y;
      EXPECT_TRUE(identical(p, samples_at(samples, x, y + n))) << x << "," << y;
      EXPECT_TRUE(identical(p, samples_at(samples, x + 5 * n, y + 3 * n))) << x << "," << y;
      EXPECT_FALSE(identical(p, samples_at(samples, x + 1, y))) << x << "," << y;
      EXPECT_FALSE(identical(p, samples_at(samples, x, y + 1))) << x << "," << y;
      expect_one_per_cell(p, k, "interleaved pixel " + std::to_string(x) + "," + std::to_string(y));
    }
  }
  // The n×n patterns are pairwise distinct.
  std::vector<std::vector<Vec2>> patterns;
  for (int y = 0; y < n; ++y)
    for (int x = 0; x < n; ++x) patterns.push_back(samples_at(samples, x, y));
  for (size_t a = 0; a < patterns.size(); ++a)
    for (size_t b = a + 1; b < patterns.size(); ++b)
      EXPECT_FALSE(identical(patterns[a], patterns[b])) << a << " vs " << b;
  // Negative pixel coordinates wrap the same way (x mod n in [0, n)).
  EXPECT_TRUE(identical(samples_at(samples, -1, -2), samples_at(samples, n - 1, n - 2)));
}

TEST(LightSamples, InterleavedWithOnePatternIsPixelIndependent) {
  const LightSamples samples(make_spec(SamplePattern::interleaved, 4, 3, 1));
  const auto p = samples_at(samples, 0, 0);
  EXPECT_TRUE(identical(p, samples_at(samples, 1, 0)));
  EXPECT_TRUE(identical(p, samples_at(samples, 57, 91)));
  expect_one_per_cell(p, 4, "interleaved n=1");
}

TEST(LightSamples, HaltonMatchesKnownValues) {
  const LightSamples samples(make_spec(SamplePattern::halton, 3));
  const auto p = samples_at(samples, 7, 8);
  ASSERT_EQ(p.size(), 9u);
  const double expected[9][2] = {
      {1.0 / 2, 1.0 / 3}, {1.0 / 4, 2.0 / 3},  {3.0 / 4, 1.0 / 9},
      {1.0 / 8, 4.0 / 9}, {5.0 / 8, 7.0 / 9},  {3.0 / 8, 2.0 / 9},
      {7.0 / 8, 5.0 / 9}, {1.0 / 16, 8.0 / 9}, {9.0 / 16, 1.0 / 27},
  };
  for (int i = 0; i < 9; ++i) {
    EXPECT_FLOAT_EQ(p[i].x, static_cast<float>(expected[i][0])) << i;
    EXPECT_FLOAT_EQ(p[i].y, static_cast<float>(expected[i][1])) << i;
  }
  // Same for every pixel and every seed.
  EXPECT_TRUE(identical(p, samples_at(samples, 0, 0)));
  EXPECT_TRUE(
      identical(p, samples_at(LightSamples(make_spec(SamplePattern::halton, 3, 77)), 1, 1)));
  // The first points do not depend on k.
  const auto q = samples_at(LightSamples(make_spec(SamplePattern::halton, 16)), 0, 0);
  for (int i = 0; i < 9; ++i) EXPECT_EQ(q[i], p[i]) << i;
}

TEST(LightSamples, PoissonPointsKeepTheirDistanceOnTheTorus) {
  for (int k : {2, 3, 4, 8, 16, 32}) {
    for (uint64_t seed : {1ull, 2ull, 12345ull}) {
      const LightSamples samples(make_spec(SamplePattern::poisson, k, seed));
      const auto p = samples_at(samples, 0, 0);
      ASSERT_EQ(p.size(), static_cast<size_t>(k * k));
      const double d = min_torus_dist(p);
      EXPECT_GE(d, 0.5 / k) << "k=" << k << " seed=" << seed << " min distance " << d * k << "/k";
      // Same for every pixel.
      EXPECT_TRUE(identical(p, samples_at(samples, 31, 17)));
    }
  }
}

TEST(LightSamples, PoissonBeatsRandomSpacing) {
  // Best candidate spreads points much better than the stratified jitter: its minimum distance
  // is several times larger at the same count.
  const int k = 16;
  const double poisson =
      min_torus_dist(samples_at(LightSamples(make_spec(SamplePattern::poisson, k, 4)), 0, 0));
  const double stratified =
      min_torus_dist(samples_at(LightSamples(make_spec(SamplePattern::stratified, k, 4)), 0, 0));
  EXPECT_GT(poisson, 0.6 / k);
  EXPECT_GT(poisson, 2.0 * stratified);
}

TEST(LightSamples, PoissonMaxKIsBuilt) {
  const LightSamples samples(make_spec(SamplePattern::poisson, 64, 9));
  const auto p = samples_at(samples, 0, 0);
  ASSERT_EQ(p.size(), 4096u);
  // Spacing check on a 64² set via a cell-neighbour scan (the O(n²) loop would be slow in ASan).
  const int k = 64;
  std::vector<std::vector<int>> cells(static_cast<size_t>(k * k));
  for (int i = 0; i < k * k; ++i) {
    const int cu = std::min(static_cast<int>(p[i].x * k), k - 1);
    const int cv = std::min(static_cast<int>(p[i].y * k), k - 1);
    cells[static_cast<size_t>(cv * k + cu)].push_back(i);
  }
  double best = 2.0;
  for (int i = 0; i < k * k; ++i) {
    const int cu = std::min(static_cast<int>(p[i].x * k), k - 1);
    const int cv = std::min(static_cast<int>(p[i].y * k), k - 1);
    for (int dv = -1; dv <= 1; ++dv)
      for (int du = -1; du <= 1; ++du)
        for (int j : cells[static_cast<size_t>(((cv + dv + k) % k) * k + (cu + du + k) % k)])
          if (j != i) best = std::min(best, torus_dist(p[i], p[j]));
  }
  // Points in non-neighbouring cells are at least 1/k apart, so `best` is the true minimum
  // whenever it is below 1/k.
  EXPECT_GE(best, 0.5 / k);
}

TEST(LightSamples, EveryPatternIsUniformOnAverage) {
  const int k = 16;
  for (SamplePattern pattern : all_sample_patterns()) {
    const LightSamples samples(make_spec(pattern, k, 21));
    for (const auto& [x, y] : {std::pair{0, 0}, std::pair{1, 0}, std::pair{13, 29}}) {
      const auto p = samples_at(samples, x, y);
      double mu = 0.0, mv = 0.0;
      for (const Vec2& s : p) {
        mu += s.x;
        mv += s.y;
      }
      mu /= static_cast<double>(p.size());
      mv /= static_cast<double>(p.size());
      EXPECT_NEAR(mu, 0.5, 0.02) << to_string(pattern) << " pixel " << x << "," << y;
      EXPECT_NEAR(mv, 0.5, 0.02) << to_string(pattern) << " pixel " << x << "," << y;
    }
  }
}

TEST(LightSamples, PixelSamplesWritesOnlyCountAndRejectsShortSpans) {
  for (SamplePattern pattern : all_sample_patterns()) {
    const LightSamples samples(make_spec(pattern, 3));
    std::vector<Vec2> big(12, Vec2(-1.0f));
    samples.pixel_samples(2, 3, big);
    for (size_t i = 9; i < big.size(); ++i) EXPECT_EQ(big[i], Vec2(-1.0f)) << to_string(pattern);
    EXPECT_TRUE(
        identical(std::vector<Vec2>(big.begin(), big.begin() + 9), samples_at(samples, 2, 3)));
    std::vector<Vec2> small(8);
    EXPECT_THROW(samples.pixel_samples(0, 0, small), std::invalid_argument) << to_string(pattern);
  }
}

}  // namespace
}  // namespace penumbra
