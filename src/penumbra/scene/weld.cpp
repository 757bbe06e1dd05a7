#include "penumbra/scene/weld.hpp"

#include <array>
#include <bit>

#include "penumbra/core/rng.hpp"

namespace penumbra {

std::vector<uint32_t> weld_positions(std::span<const Vec3> positions) {
  const size_t n = positions.size();
  std::vector<uint32_t> weld(n);
  auto bits_of = [&](size_t v) {
    const Vec3& p = positions[v];
    return std::array<uint32_t, 3>{std::bit_cast<uint32_t>(p.x + 0.0f),  // + 0.0f: −0 → +0
                                   std::bit_cast<uint32_t>(p.y + 0.0f),
                                   std::bit_cast<uint32_t>(p.z + 0.0f)};
  };
  // Open addressing over representatives, linear probing; a slot holds a representative + 1
  // (0: empty). The table is at least twice the vertex count, so probes stay short.
  size_t size = 16;
  while (size < 2 * n) size *= 2;
  const size_t mask = size - 1;
  std::vector<uint32_t> slot(size, 0);
  for (size_t v = 0; v < n; ++v) {
    const std::array<uint32_t, 3> bits = bits_of(v);
    size_t i = splitmix64(uint64_t{bits[0]} << 32 | bits[1]) ^ splitmix64(uint64_t{bits[2]});
    for (i &= mask;; i = (i + 1) & mask) {
      if (slot[i] == 0) {
        slot[i] = static_cast<uint32_t>(v) + 1;
        weld[v] = static_cast<uint32_t>(v);
        break;
      }
      if (bits_of(slot[i] - 1) == bits) {
        weld[v] = slot[i] - 1;
        break;
      }
    }
  }
  return weld;
}

}  // namespace penumbra
