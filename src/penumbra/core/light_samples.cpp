// LightSamples: light sample positions in light uv space [0,1)² for every sampling method.
//
// Every random pattern is a pure function of (spec, pixel): the generators are seeded PCG32 streams
// (penumbra/core/rng.hpp), so the positions never depend on thread count or evaluation order.
#include "penumbra/core/light_samples.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include "penumbra/core/error.hpp"
#include "penumbra/core/rng.hpp"

namespace penumbra {

namespace {

constexpr int kMaxK = 64;

// Stream ids / seed tags keep the random sources of the different patterns independent.
constexpr uint64_t kStratifiedStream = 0;  // the one stratified pattern (and decorrelated base)
constexpr uint64_t kInterleavedStreamBase = 1;  // interleaved pattern j uses stream 1 + j
constexpr uint64_t kShiftSeedTag = 0x5eed5a17c0ffee01ull;   // per-pixel shifts (decorrelated)
constexpr uint64_t kPoissonSeedTag = 0x9015504d15c5eedull;  // best-candidate candidates

// Largest float below 1.
const float kBelowOne = std::nextafter(1.0f, 0.0f);

/// x rounded to float and clamped into [0, 1).
float to_unit(double x) {
  const float f = static_cast<float>(x);
  if (!(f >= 0.0f)) return 0.0f;  // also catches NaN (never produced, but stay in range)
  return std::min(f, kBelowOne);
}

/// Coordinate (c + jitter) / k as a float that lies in cell c: c/k <= value < (c+1)/k exactly.
/// (double(f) * k is exact for a float f and k <= 64, so the cell test below is exact.)
float in_cell(int c, double jitter, int k) {
  float f = static_cast<float>((c + jitter) / k);
  while (static_cast<double>(f) * k >= c + 1) f = std::nextafter(f, 0.0f);
  while (static_cast<double>(f) * k < c) f = std::nextafter(f, 1.0f);
  return f;
}

/// One jittered sample per cell of the k×k grid, sample i in cell (i % k, i / k).
std::vector<Vec2> make_stratified(int k, Pcg32 rng) {
  std::vector<Vec2> out;
  out.reserve(static_cast<size_t>(k) * k);
  for (int j = 0; j < k; ++j) {
    for (int i = 0; i < k; ++i) {
      const double ju = rng.next_float();
      const double jv = rng.next_float();
      out.emplace_back(in_cell(i, ju, k), in_cell(j, jv, k));
    }
  }
  return out;
}

std::vector<Vec2> make_grid(int k) {
  std::vector<Vec2> out;
  out.reserve(static_cast<size_t>(k) * k);
  for (int j = 0; j < k; ++j)
    for (int i = 0; i < k; ++i)
      out.emplace_back(static_cast<float>((i + 0.5) / k), static_cast<float>((j + 0.5) / k));
  return out;
}

double radical_inverse(uint32_t n, uint32_t base) {
  const double inv_base = 1.0 / base;
  double inv = inv_base;
  double r = 0.0;
  while (n > 0) {
    r += inv * (n % base);
    n /= base;
    inv *= inv_base;
  }
  return r;
}

/// Halton points 1 .. count in bases (2, 3); index 0 (the origin) is skipped.
std::vector<Vec2> make_halton(int count) {
  std::vector<Vec2> out;
  out.reserve(static_cast<size_t>(count));
  for (int i = 1; i <= count; ++i) {
    const auto n = static_cast<uint32_t>(i);
    out.emplace_back(to_unit(radical_inverse(n, 2)), to_unit(radical_inverse(n, 3)));
  }
  return out;
}

/// Squared distance on the unit torus.
double torus_dist2(const DVec2& a, const DVec2& b) {
  double dx = std::abs(a.x - b.x);
  double dy = std::abs(a.y - b.y);
  dx = std::min(dx, 1.0 - dx);
  dy = std::min(dy, 1.0 - dy);
  return dx * dx + dy * dy;
}

/// Mitchell's best-candidate algorithm on the torus (Mitchell 1991): point i is the best of
/// m * i uniform candidates, the one farthest (toroidal distance) from the points already placed.
/// A uniform grid of ~1 point per cell answers the nearest-point queries, and a candidate is
/// dropped as soon as it is known to lose against the best one so far.
///
/// The work is ~m n² / 2 candidates for n points, so m = 10 is lowered (down to 1) for the largest
/// patterns to keep the total under kCandidateBudget: m = 10 up to k = 32 (about 0.1 s), m = 1 at
/// k = 64 (about 0.25 s). The spacing barely changes: the minimum toroidal distance measured over
/// seeds is about 0.7-0.8/k with m = 10 (lowest for k = 2, 3) and 0.76/k at k = 64 with m = 1.
class BestCandidate {
 public:
  static constexpr int kMaxCandidateFactor = 10;
  static constexpr double kCandidateBudget = 1.2e7;

  static int candidate_factor(int count) {
    const double n = static_cast<double>(count);
    const double m = std::floor(kCandidateBudget / (0.5 * n * n));
    return static_cast<int>(std::clamp(m, 1.0, static_cast<double>(kMaxCandidateFactor)));
  }

  BestCandidate(int count, int grid) : grid_(grid), head_(static_cast<size_t>(grid) * grid, -1) {
    points_.reserve(static_cast<size_t>(count));
    next_.reserve(static_cast<size_t>(count));
  }

  std::vector<Vec2> generate(int count, Pcg32 rng) {
    const int factor = candidate_factor(count);
    for (int i = 0; i < count; ++i) {
      const int candidates = std::max(1, factor * i);
      DVec2 best(0.0);
      double best_d2 = -1.0;
      for (int c = 0; c < candidates; ++c) {
        const double u = rng.next_float();
        const double v = rng.next_float();
        const DVec2 p(u, v);
        const double d2 = nearest_dist2_above(p, best_d2);
        if (d2 > best_d2) {
          best_d2 = d2;
          best = p;
        }
      }
      insert(best);
    }
    std::vector<Vec2> out;
    out.reserve(points_.size());
    for (const DVec2& p : points_) out.emplace_back(to_unit(p.x), to_unit(p.y));
    return out;
  }

 private:
  int cell_of(double x) const { return std::min(static_cast<int>(x * grid_), grid_ - 1); }
  // c in [-grid_, 2 grid_): the rings never reach farther.
  int wrap(int c) const { return c < 0 ? c + grid_ : (c >= grid_ ? c - grid_ : c); }

  void insert(const DVec2& p) {
    const int id = static_cast<int>(points_.size());
    const size_t cell = static_cast<size_t>(cell_of(p.y)) * grid_ + cell_of(p.x);
    points_.push_back(p);
    next_.push_back(head_[cell]);
    head_[cell] = id;
  }

  /// Squared distance from p to the nearest placed point, or any value <= floor_d2 as soon as it
  /// is known to be <= floor_d2 (then p cannot beat the best candidate). Infinity when empty.
  double nearest_dist2_above(const DVec2& p, double floor_d2) const {
    double best = std::numeric_limits<double>::infinity();
    const auto n = static_cast<int>(points_.size());
    if (n < 2 * grid_ + 8) {  // few points: the rings would visit mostly empty cells
      for (const DVec2& q : points_) {
        best = std::min(best, torus_dist2(p, q));
        if (best <= floor_d2) return best;
      }
      return best;
    }
    const int cx = cell_of(p.x);
    const int cy = cell_of(p.y);
    const double cell = 1.0 / grid_;
    const int max_ring = grid_ / 2 + 1;  // rings beyond this only revisit cells
    for (int r = 0; r <= max_ring; ++r) {
      // Every point in ring r is at least (r - 1) cells away along x or y.
      const double ring_min = std::max(0, r - 1) * cell;
      if (ring_min * ring_min >= best) break;
      for (int dy = -r; dy <= r; ++dy) {
        const bool edge_row = (dy == -r || dy == r);
        const int step = edge_row ? 1 : 2 * r;
        for (int dx = -r; dx <= r; dx += std::max(step, 1)) {
          const size_t c = static_cast<size_t>(wrap(cy + dy)) * grid_ + wrap(cx + dx);
          for (int id = head_[c]; id >= 0; id = next_[static_cast<size_t>(id)]) {
            best = std::min(best, torus_dist2(p, points_[static_cast<size_t>(id)]));
            if (best <= floor_d2) return best;
          }
        }
      }
    }
    return best;
  }

  int grid_;
  std::vector<DVec2> points_;
  std::vector<int> head_;  // first point of each cell, -1 when empty
  std::vector<int> next_;  // next point in the same cell
};

size_t interleave_index(int x, int y, int n) {
  const int ix = ((x % n) + n) % n;
  const int iy = ((y % n) + n) % n;
  return static_cast<size_t>(iy) * static_cast<size_t>(n) + static_cast<size_t>(ix);
}

/// Adds the shift s to each coordinate and wraps into [0, 1): a Cranley–Patterson rotation.
float wrap_add(float a, float s) {
  float r = a + s;  // a, s in [0, 1) so r in [0, 2)
  if (r >= 1.0f) r -= 1.0f;
  return r;  // r - 1 is exact for r in [1, 2), so the result stays in [0, 1)
}

}  // namespace

std::string_view to_string(SamplePattern pattern) {
  switch (pattern) {
    case SamplePattern::grid:
      return "grid";
    case SamplePattern::stratified:
      return "stratified";
    case SamplePattern::decorrelated:
      return "decorrelated";
    case SamplePattern::interleaved:
      return "interleaved";
    case SamplePattern::halton:
      return "halton";
    case SamplePattern::poisson:
      return "poisson";
  }
  return "unknown";
}

std::optional<SamplePattern> parse_sample_pattern(std::string_view name) {
  for (SamplePattern pattern : all_sample_patterns())
    if (to_string(pattern) == name) return pattern;
  return std::nullopt;
}

const std::vector<SamplePattern>& all_sample_patterns() {
  static const std::vector<SamplePattern> patterns = {
      SamplePattern::grid,        SamplePattern::stratified, SamplePattern::decorrelated,
      SamplePattern::interleaved, SamplePattern::halton,     SamplePattern::poisson,
  };
  return patterns;
}

LightSamples::LightSamples(const LightSampleSpec& spec) : spec_(spec) {
  if (spec.k < 1 || spec.k > kMaxK)
    throw Error("light samples: k must be in [1, " + std::to_string(kMaxK) + "], got " +
                std::to_string(spec.k));
  if (spec.interleave_n < 1 || spec.interleave_n > 16)
    throw Error("light samples: interleave_n must be in 1..16, got " +
                std::to_string(spec.interleave_n));

  const int k = spec.k;
  switch (spec.pattern) {
    case SamplePattern::grid:
      shared_ = make_grid(k);
      break;
    case SamplePattern::stratified:
      shared_ = make_stratified(k, Pcg32(spec.seed, kStratifiedStream));
      break;
    case SamplePattern::decorrelated:
      // [Forest 2008 §4.2.1] the base is the stratified pattern itself (same seed, same stream),
      // so decorrelated = stratified + a per-pixel toroidal shift.
      shared_ = make_stratified(k, Pcg32(spec.seed, kStratifiedStream));
      break;
    case SamplePattern::interleaved: {
      // [Forest 2008 §4.2.2] (Keller & Heidrich 2001): n×n distinct stratified patterns, one
      // PCG32 stream each, tiled over the screen.
      const size_t patterns = static_cast<size_t>(spec.interleave_n) * spec.interleave_n;
      interleaved_.reserve(patterns);
      for (size_t j = 0; j < patterns; ++j)
        interleaved_.push_back(make_stratified(k, Pcg32(spec.seed, kInterleavedStreamBase + j)));
      break;
    }
    case SamplePattern::halton:
      shared_ = make_halton(k * k);
      break;
    case SamplePattern::poisson:
      shared_ = BestCandidate(k * k, k).generate(k * k, Pcg32(spec.seed ^ kPoissonSeedTag));
      break;
  }
}

bool LightSamples::per_pixel() const {
  return spec_.pattern == SamplePattern::decorrelated ||
         spec_.pattern == SamplePattern::interleaved;
}

void LightSamples::pixel_samples(int x, int y, std::span<Vec2> light_uv) const {
  const auto n = static_cast<size_t>(count());
  if (light_uv.size() < n)
    throw std::invalid_argument("LightSamples::pixel_samples: output span smaller than count()");
  switch (spec_.pattern) {
    case SamplePattern::decorrelated: {
      // [Forest 2008 §4.2.1] "randomly rotating the initial sampling pattern" per receiver: a
      // Cranley–Patterson rotation (toroidal shift) of the stratified base, drawn from a PCG32
      // stream keyed by the pixel, so it is a pure function of (seed, x, y).
      const uint64_t key = (static_cast<uint64_t>(static_cast<uint32_t>(y)) << 32) |
                           static_cast<uint64_t>(static_cast<uint32_t>(x));
      Pcg32 rng(spec_.seed ^ kShiftSeedTag, key);
      const float su = rng.next_float();
      const float sv = rng.next_float();
      for (size_t i = 0; i < n; ++i)
        light_uv[i] = Vec2(wrap_add(shared_[i].x, su), wrap_add(shared_[i].y, sv));
      return;
    }
    case SamplePattern::interleaved: {
      const std::vector<Vec2>& pattern = interleaved_[interleave_index(x, y, spec_.interleave_n)];
      std::copy_n(pattern.begin(), n, light_uv.begin());
      return;
    }
    default:
      std::copy_n(shared_.begin(), n, light_uv.begin());
      return;
  }
}

std::span<const Vec2> LightSamples::shared_samples() const {
  if (per_pixel()) return {};
  return shared_;
}

}  // namespace penumbra
