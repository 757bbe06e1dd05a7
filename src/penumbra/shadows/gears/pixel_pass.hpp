// GEARS step 4 and 5 for the pixels of one work item [Wang 2014 §4.2]: the item's candidate
// triangles gathered and culled (per item, per sample group, per pixel), rasterized onto each
// pixel's light-sample bitmask, and the pixel shaded from its bits.
#pragma once

#include <cstdint>
#include <vector>

#include "penumbra/render/visibility.hpp"
#include "penumbra/shadows/gears/frame_setup.hpp"
#include "penumbra/shadows/gears/item_cull.hpp"
#include "penumbra/shadows/gears/raster.hpp"

namespace penumbra {
struct ShadowContext;
}

namespace penumbra::gears {

class EdgeLut;
struct Solids;

/// Which rasterizer and which shading one frame uses, decided once from the light, the samples
/// and the options.
struct FramePlan {
  int n = 0, k = 0, words = 0;  // samples, grid side, mask words per pixel
  bool point = false, sphere = false, per_pixel_samples = false;
  bool use_lut = false;         // the §4.3 LUT (shared samples, area lights)
  bool use_rows = false;        // row spans (the regular grid, k ≤ 32, area lights)
  bool simple_weights = false;  // V = emitting samples not blocked / emitting samples
  // Each pixel is shaded from its own bits as soon as they are known: no frame-size mask array.
  bool shade_in_place = false;
  bool deepest_first = false;  // a pixel's candidates nearest to it first
};

FramePlan plan_frame(const ShadowContext& ctx, const Options& options, const LightSetup& setup,
                     const SharedSamples& samples);

/// Work counters of the rasterization, per thread, summed at the end (gears.cpp names them).
struct RasterTally {
  uint64_t grid = 0;        // (cell list × samples) pairs: the paper's per-cell lists
  uint64_t gathered = 0;    // list entries read per work item
  uint64_t item = 0;        // kept by the per-item cull, × samples
  uint64_t group = 0;       // kept by the per-group cull, × the group's samples
  uint64_t scanned = 0;     // item candidates the per-pixel cull read
  uint64_t tested = 0;      // set up
  uint64_t in_volume = 0;   // the pixel lies in their shadow volume
  uint64_t hidden = 0;      // in the volume, but their shadow box held only blocked samples
  uint64_t necessary = 0;   // covered some sample
  uint64_t early_full = 0;  // pixels whose mask filled before their candidates ran out
  RasterTally& operator+=(const RasterTally& o);
};

/// Per-thread buffers of the rasterization pass.
struct Scratch {
  CandidateBatch batch, group_batch, pixel_batch;  // a work item's candidates, a group's, a pixel's
  std::vector<int> group_order, group_ends;        // the item's samples in groups (group_samples)
  LineBatch lines;
  std::vector<Vec2> light_uv;
  std::vector<float> su, sv, vis, trans;  // trans: the pixel's per-sample transmittance
  std::vector<Vec2> shade_uv;
  std::vector<float> ix, iy, iz;  // the work item's samples, for its cull bounds
  std::vector<float> gx, gy, gz;  // one group's
  std::vector<Vec3> gp;           // one group's samples (unmirrored light space)
  std::vector<uint64_t> outside;  // the item's samples: Solids::outside
  std::vector<uint64_t> cover, blocked, emit, words;
  std::vector<uint64_t> own;        // a pixel's mask words, where the frame holds none
  uint32_t rows[32], tri_rows[32];  // k ≤ 32 rows (row spans write whole 16-row registers)
};

/// Step 5 for one pixel: V from its mask words (and per-sample transmittances, semi-opaque
/// occluders only), weighted by light_weights.hpp exactly as `raytrace` weights its rays.
void shade_pixel(const ShadowContext& ctx, const FramePlan& plan, const SharedSamples& samples,
                 uint32_t pixel, const uint64_t* mask, const float* transmittance, Scratch& scratch,
                 Visibility& out);

/// A work item: a run of a cell's samples (indices into PixelCells::sorted).
struct WorkItem {
  uint32_t cell, begin, end;
};

/// Everything one grid pass (one side of the light plane) reads; shared by the threads.
struct SidePass {
  const ShadowContext& ctx;
  const Options& options;
  const FramePlan& plan;
  const LightSetup& setup;
  const SharedSamples& samples;
  const Solids& solids;
  const EdgeLut* lut;
  const PixelCells& cells;
  const CellTriangles& table;
  const FlatLight& flat;
  const PackedTriangle* packed;
  const TrianglePlane* planes;
  SampleMasks& masks;  // each pixel writes its own words only (empty when shade_in_place)
  Visibility& out;     // each pixel writes its own V only
};

/// Computes (and, where the plan says, shades) the masks of the item's pixels.
void rasterize_item(const SidePass& pass, const WorkItem& item, Scratch& scratch,
                    RasterTally& tally);

}  // namespace penumbra::gears
