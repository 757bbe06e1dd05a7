// GEARS unit tests: light-space triangles as the candidate batch a work item's gather would
// produce (opaque, no solid, cull bounds that keep them all), for the setup and rasterizer tests.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "penumbra/shadows/gears/raster.hpp"
#include "penumbra/shadows/gears/solids.hpp"

namespace penumbra::test {

inline gears::CandidateBatch opaque_batch(const std::vector<std::array<Vec3, 3>>& tris) {
  std::vector<gears::PackedTriangle> packed(tris.size());
  std::vector<gears::CellPair> pairs(tris.size());
  for (size_t t = 0; t < tris.size(); ++t) {
    for (int v = 0; v < 3; ++v)
      for (int c = 0; c < 3; ++c) packed[t].v[3 * v + c] = tris[t][v][c];
    packed[t].zmin = 0.0f;
    packed[t].hx0 = packed[t].hy0 = kInfinity, packed[t].hx1 = packed[t].hy1 = -kInfinity;
    packed[t].opaque = 1, packed[t].solid = gears::kNoSolid;
    pairs[t] = {0, static_cast<uint32_t>(t)};
  }
  const std::vector<gears::TrianglePlane> planes(tris.size());
  const gears::ItemBounds all{kInfinity, -kInfinity, kInfinity, -kInfinity, kInfinity};
  gears::CandidateBatch batch;
  batch.gather(packed.data(), planes.data(), pairs.data(), pairs.data() + pairs.size(), all);
  return batch;
}

}  // namespace penumbra::test
