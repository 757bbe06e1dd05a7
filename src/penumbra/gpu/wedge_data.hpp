// Penumbra wedges and screen-tile bins as the compute shaders read them (shaders/dcs.glsl), shared
// by `dcs` and `wedges` on Vulkan.
#pragma once

#include <algorithm>
#include <cstdint>
#include <vector>

#include "penumbra/core/math.hpp"
#include "penumbra/shadows/wedges/geometry.hpp"

namespace penumbra::gpu {

inline void put3(double* out, const DVec3& v) {
  out[0] = v.x, out[1] = v.y, out[2] = v.z;
}

/// dcs.glsl Wedge (scalar layout): planes (n, d), the edge, the plane tolerance, its edge index.
struct WedgeGpu {
  double planes[kMaxWedgePlanes][4];
  double e0[3], e1[3];
  double tolerance;
  int32_t plane_count;
  uint32_t edge;
};
static_assert(sizeof(WedgeGpu) == 576);

inline WedgeGpu to_gpu(const Wedge& src, uint32_t edge) {
  WedgeGpu dst{};
  for (int p = 0; p < src.plane_count; ++p) {
    put3(dst.planes[p], src.planes[p].n);
    dst.planes[p][3] = src.planes[p].d;
  }
  put3(dst.e0, src.e0), put3(dst.e1, src.e1);
  dst.tolerance = src.tolerance;
  dst.plane_count = src.plane_count;
  dst.edge = edge;
  return dst;
}

/// Per-tile bins as CSR: entries of tile t are entries[begin[t], begin[t + 1]).
struct Bins {
  std::vector<uint32_t> begin{0}, entries;
  uint32_t longest = 0;
  explicit Bins(const std::vector<std::vector<uint32_t>>& bins) {
    for (const std::vector<uint32_t>& bin : bins) {
      entries.insert(entries.end(), bin.begin(), bin.end());
      begin.push_back(static_cast<uint32_t>(entries.size()));
      longest = std::max(longest, static_cast<uint32_t>(bin.size()));
    }
    if (begin.size() == 1) begin.push_back(0);
  }
};

}  // namespace penumbra::gpu
