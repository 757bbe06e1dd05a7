#include "penumbra/shadows/gears/lut.hpp"

#include <algorithm>
#include <cmath>

namespace penumbra::gears {

namespace {

/// Diamond angle of a direction in [0, 4): monotonic in the true angle, no trigonometry.
inline float diamond_angle(float x, float y) {
  if (y >= 0.0f) return x >= 0.0f ? y / (x + y) : 1.0f - x / (-x + y);
  return x < 0.0f ? 2.0f - y / (-x - y) : 3.0f + x / (x - y);
}

/// Unit direction of diamond angle p.
Vec2 diamond_direction(float p) {
  Vec2 d;
  if (p < 1.0f)
    d = Vec2(1.0f - p, p);
  else if (p < 2.0f)
    d = Vec2(1.0f - p, 2.0f - p);
  else if (p < 3.0f)
    d = Vec2(p - 3.0f, 2.0f - p);
  else
    d = Vec2(p - 3.0f, p - 4.0f);
  return glm::normalize(d);
}

}  // namespace

EdgeLut::EdgeLut(std::span<const Vec2> samples, int angles, int offsets)
    : angles_(std::max(4, angles)),
      offsets_(std::max(2, offsets)),
      words_((static_cast<int>(samples.size()) + 63) / 64),
      radius_(0.0f) {
  for (const Vec2& s : samples) radius_ = std::max(radius_, glm::length(s - Vec2(0.5f)));
  radius_ = std::max(radius_, 1e-6f);
  all_.assign(words_, 0);
  none_.assign(words_, 0);
  for (size_t s = 0; s < samples.size(); ++s) all_[s >> 6] |= uint64_t{1} << (s & 63);
  table_.assign(static_cast<size_t>(angles_) * offsets_ * words_, 0);
  for (int ai = 0; ai < angles_; ++ai) {
    const Vec2 n = diamond_direction(4.0f * (ai + 0.5f) / angles_);
    for (int oi = 0; oi < offsets_; ++oi) {
      // Signed distance of the centre from the line, bin centre, in [−R, R].
      const float rho = radius_ * (2.0f * (oi + 0.5f) / offsets_ - 1.0f);
      uint64_t* w = &table_[(static_cast<size_t>(ai) * offsets_ + oi) * words_];
      for (size_t s = 0; s < samples.size(); ++s)
        if (glm::dot(n, samples[s] - Vec2(0.5f)) + rho >= 0.0f)
          w[s >> 6] |= uint64_t{1} << (s & 63);
    }
  }
}

const uint64_t* EdgeLut::lookup(float a, float b, float c) const {
  const float len = std::sqrt(b * b + c * c);
  const float centre = a + 0.5f * (b + c);
  if (!(len > 0.0f)) return centre >= 0.0f ? all_.data() : none_.data();
  const float rho = centre / len;
  if (rho >= radius_) return all_.data();
  if (rho < -radius_) return none_.data();
  const int ai = std::min(angles_ - 1, static_cast<int>(diamond_angle(b, c) * (angles_ * 0.25f)));
  const int oi =
      std::clamp(static_cast<int>((rho / radius_ + 1.0f) * 0.5f * offsets_), 0, offsets_ - 1);
  return &table_[(static_cast<size_t>(ai) * offsets_ + oi) * words_];
}

}  // namespace penumbra::gears
