// Deterministic random numbers: PCG32 (O'Neill 2014) seeded through SplitMix64, so that a seed and
// a stream id (e.g. a pixel index) always give the same sequence on every platform and thread
// count.
#pragma once

#include <cstdint>

namespace penumbra {

inline uint64_t splitmix64(uint64_t x) {
  x += 0x9e3779b97f4a7c15ull;
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ull;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebull;
  return x ^ (x >> 31);
}

class Pcg32 {
 public:
  explicit Pcg32(uint64_t seed, uint64_t stream = 0) {
    inc_ = (splitmix64(stream) << 1u) | 1u;
    state_ = 0;
    next_u32();
    state_ += splitmix64(seed);
    next_u32();
  }
  uint32_t next_u32() {
    const uint64_t old = state_;
    state_ = old * 6364136223846793005ull + inc_;
    const uint32_t xorshifted = static_cast<uint32_t>(((old >> 18u) ^ old) >> 27u);
    const uint32_t rot = static_cast<uint32_t>(old >> 59u);
    return (xorshifted >> rot) | (xorshifted << ((-rot) & 31));
  }
  /// Uniform in [0, 1): 24 random mantissa bits, never 1.0f.
  float next_float() { return static_cast<float>(next_u32() >> 8) * 0x1p-24f; }

 private:
  uint64_t state_ = 0;
  uint64_t inc_ = 1;
};

}  // namespace penumbra
