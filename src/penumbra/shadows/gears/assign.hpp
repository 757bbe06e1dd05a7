// GEARS step 3.3: triangle → grid-cell assignment [Wang 2014 §3.1 (3.3), §4.2]. Each occluder's
// shadow volume (3 vertices extruded through the light corners to the far plane, 15 points for a
// rectangle) is projected with the grid camera; the triangle goes to the cells of the 2D AABB,
// retracted to the deepest sample of the touched cells. Pairs (triID, cellID) are counted, prefix
// summed, written and radix sorted by cell.
#pragma once

#include <cstdint>
#include <vector>

#include "penumbra/core/stats.hpp"
#include "penumbra/core/uninit_vector.hpp"
#include "penumbra/shadows/gears/grid_camera.hpp"
#include "penumbra/shadows/gears/radix_sort.hpp"

namespace penumbra::gears {

/// Occluding triangles in light space (structure of arrays, the layout the rasterizer gathers).
struct TriangleSoup {
  // Written in full right after resize(), in parallel: not zeroed first.
  UninitVector<float> x[3], y[3], z[3];  // vertex c of triangle t: (x[c][t], y[c][t], z[c][t])
  UninitVector<uint32_t> mesh, prim;     // where the triangle came from
  UninitVector<uint8_t> opaque;          // 1: opaque material (no alpha texture, no transmittance)
  size_t size() const { return mesh.size(); }
  void resize(size_t n) {
    for (int c = 0; c < 3; ++c) x[c].resize(n), y[c].resize(n), z[c].resize(n);
    mesh.resize(n), prim.resize(n), opaque.resize(n);
  }
};

/// Pixel samples bucketed by grid cell (step 3.2), with the per-cell maximum depth.
struct PixelCells {
  CellPairs sorted;                  // (cell, pixel index), sorted by cell then pixel
  std::vector<uint32_t> begin, end;  // per cell, into `sorted`
  std::vector<float> max_z;          // per cell, −inf when empty
  std::vector<float> sample_z;       // per entry of `sorted`: the sample's depth
  std::vector<Vec3> box_lo,
      box_hi;  // per cell, the samples' bounding box (this pass's coordinates)
};

struct AssignOptions {
  bool retraction = true;       // re-extrude to the deepest sample of the touched cells [§3.1]
  bool cell_depth_cull = true;  // skip cells whose deepest sample is nearer than the triangle
};

struct AssignStats {
  uint64_t pairs = 0;                     // (triangle, cell) pairs written
  uint64_t pairs_without_retraction = 0;  // non-empty cells of the first (far-plane) AABB
  uint64_t aabb_cells = 0;                // cellsN of the paper: area of the final AABBs
  uint64_t culled_behind_light = 0;       // entirely behind the light plane
  uint64_t culled_beyond_samples = 0;     // entirely deeper than every sample (or off the grid)
  uint64_t straddling_light = 0;          // reach the light's depth: not extruded (see assign)
  double count_ms = 0, prefix_ms = 0, write_ms = 0, sort_ms = 0;
};

/// Candidate triangles per cell: cell c's triangles are pairs[begin[c] .. end[c]), by ascending
/// nearest depth zmin (ties: ascending id).
struct CellTriangles {
  CellPairs pairs;  // sorted by cell
  std::vector<uint32_t> begin, end;
  std::vector<float> zmin;  // per triangle: its nearest depth from the light (this pass's sign)
  size_t bytes() const {
    return pairs.capacity() * sizeof(CellPair) +
           (begin.capacity() + end.capacity() + zmin.capacity()) * 4;
  }
};

/// `side` = +1 uses soup depths as they are, −1 mirrors them (the pass for samples behind the
/// light plane).
CellTriangles assign_triangles(const GridCamera& camera, const TriangleSoup& soup, int side,
                               const PixelCells& cells, const AssignOptions& options,
                               AssignStats& stats);

}  // namespace penumbra::gears

namespace penumbra::gears {

/// Step 3.2: each sample (pixel index, light-space point with this pass's depth sign) to the cell
/// it projects to; per-cell maximum depth for the retraction [Wang 2014 §3.1 (3.2)].
PixelCells bucket_pixels(const GridCamera& camera, const std::vector<uint32_t>& pixels,
                         const std::vector<Vec3>& points);

}  // namespace penumbra::gears
