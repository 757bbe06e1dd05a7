// GEARS step 4: per-pixel visibility bitmasks by edge-plane rasterization [Wang 2014 §4.2].
// Seen from pixel point P, triangle ABC blocks the light point X(u, v) iff X lies in the three
// edge planes' positive half-spaces (P, A, B), (P, B, C), (P, C, A) — all oriented by
// s = sign(det(A−P, B−P, C−P)) — and beyond the triangle's plane (segment parameter t ≤ 1, which is
// Σ s·e_i(X) ≥ |det|). On the light plane each of the four tests is a line in light uv, so no
// perspective division or clipping is needed: triangles crossing the plane of P or of the light
// are handled exactly by construction.
#pragma once

#include <algorithm>
#include <cstdint>
#include <vector>

#include "penumbra/core/math.hpp"
#include "penumbra/core/uninit_vector.hpp"
#include "penumbra/shadows/gears/assign.hpp"
#include "penumbra/shadows/gears/item_cull.hpp"

namespace penumbra::gears {

// Triangles set up together: one AVX-512 register of floats, two AVX2 or four SSE4/NEON registers
// (the kernels are dispatched per CPU: core/simd.hpp).
inline constexpr int kLanes = 16;

/// The sample box and grid setup_batch tests a shadow's bounding box against (its uv_lo, uv_hi,
/// grid_k arguments), for CandidateBatch::keep.
struct ShadowBoxCull {
  Vec2 uv_lo{0.0f}, uv_hi{1.0f};
  int grid_k = 0;
};

/// Some samples' box (unmirrored light space) and the solids (gears/solids.hpp) they all lie
/// outside of.
struct SampleBox {
  Vec3 lo{0.0f}, hi{0.0f};
  uint64_t outside = 0;
};

/// Candidate triangles of one work item (or of one pixel), in light space (SoA, padded to 16).
struct CandidateBatch {
  // Each fill writes every lane it later reads (the lanes up to `padded`): not zeroed first.
  UninitVector<float> v[9];  // ax ay az bx by bz cx cy cz
  // Cull bounds (PackedTriangle: zmin, hx0, hx1, hy0, hy1; TrianglePlane), for the per-pixel cull.
  UninitVector<float> zmin, hx0, hx1, hy0, hy1;
  UninitVector<float> nx, ny, nz, nd, n1, lmin, lmax;
  UninitVector<uint32_t> tri;
  UninitVector<uint32_t> opaque;  // 1: opaque material
  UninitVector<uint32_t> solid;   // gears/solids.hpp: the triangle's solid, or kNoSolid
  int count = 0;
  int padded = 0;
  int read = 0;  // list entries the last gather() read
  /// Gathers the candidates of [begin, end) that may block one of the work item's samples
  /// (gears/item_cull.hpp: depth cut and edge-angle slabs).
  void gather(const PackedTriangle* tris, const TrianglePlane* planes, const CellPair* begin,
              const CellPair* end, const ItemBounds& item);
  /// Drops, in place and in order, the faces of solids that every sample of `samples` lies
  /// outside of and strictly behind: keep()'s solid test for the whole box, at twice its
  /// tolerance, so the samples' own tests drop all that this drops.
  void drop_solid_back_faces(const SampleBox& samples);
  /// The candidates from[begin, end) (a work item's) that may block sample `p` (unmirrored light
  /// space; `pixel`: its ItemBounds): the item's tests for this one sample and the
  /// separating-plane test (TrianglePlane), in the same order. A pixel sets up only what this
  /// keeps. (The plane test on a whole item's box culls next to nothing: the planes of a curved
  /// surface cut it.)
  /// `box` (axis-aligned pixel lights only): also setup_batch's shadow-box test, with the same
  /// arithmetic, so the set-up survivors (and so the masks) do not change.
  /// `rows` (with `box`, grid samples): the pixel's mask so far; candidates whose shadow box holds
  /// only samples already blocked there are dropped too (hidden_lanes).
  /// `outside` (Solids::outside of p): the solids whose faces with p strictly on their negative
  /// side are dropped too (gears/solids.hpp).
  void keep(const CandidateBatch& from, int begin, int end, const ItemBounds& pixel, const Vec3& p,
            const ShadowBoxCull* box = nullptr, const uint32_t* rows = nullptr,
            uint64_t outside = 0);
  /// The candidates of an item batch `from` that pass may_block() for `group` (the ItemBounds of
  /// some of the item's samples: depth cut and edge-angle slabs), in the same order, with every
  /// array (a batch keep() can cull from). Each sample's own slab test implies its group's (the
  /// bounds are min/max of the same float expressions), so keep() on this batch kept exactly what
  /// it kept on `from`.
  /// `points` (unmirrored light space, `outside`: the solids every one of them lies outside of):
  /// also the separating-plane and solid tests of keep() for all of them at once, with twice
  /// keep()'s tolerance, so that what this drops keep() drops for each of them.
  void narrow(const CandidateBatch& from, const ItemBounds& group, const Vec3* points = nullptr,
              int point_count = 0, uint64_t outside = 0);
  /// End of the prefix of an item batch whose triangles pass the depth cut `zmin <= zmax`: the
  /// gather keeps its cell list's (zmin, id) order, so a pixel's depth cut is a prefix too, and
  /// keep() need not scan beyond it (it would reject every lane there).
  int depth_prefix(float zmax) const {
    return static_cast<int>(std::partition_point(zmin.begin(), zmin.begin() + count,
                                                 [zmax](float z) { return z <= zmax; }) -
                            zmin.begin());
  }
  /// The lanes of batch [first, first+16) whose triangle is opaque.
  uint32_t opaque_lanes(int first) const {
    uint32_t m = 0;
    for (int l = 0; l < kLanes; ++l) m |= opaque[first + l] << l;
    return m;
  }

 private:
  /// Room for `most` lanes in every array; what they held is not kept (each fill starts over).
  void reserve(size_t most);
  size_t reserved_ = 0;  // every array above holds at least this many elements
  void pad();
  void pad_setup();
};

/// The sample cells of 16 lanes' shadow boxes (setup_batch or keep() with a grid): columns
/// box[0] … box[1], rows box[2] … box[3], clamped to the grid; valid for the lanes in `boxed`
/// (all three vertices between the light and the pixel, where the shadow is the triangle of the
/// vertices' projections). Every sample such a lane covers lies in its box (the box is widened
/// beyond the projections' rounding, as for the shadow-box test that rejects a lane).
struct ShadowCells {
  alignas(64) int32_t box[4][kLanes];
  uint32_t boxed = 0;
};

/// One pixel's light, in light space: light point X(u, v) = p + w + u·eu + v·ev.
struct PixelLight {
  Vec3 p{0.0f};  // the pixel's shadow origin
  Vec3 w{0.0f};  // light corner − p
  Vec3 eu{1, 0, 0}, ev{0, 1, 0};
  bool axis_aligned = true;  // eu = (1,0,0), ev = (0,1,0): the frame of the light space itself
};

/// The four lines of 16 triangles: triangle l blocks (u, v) iff a[m][l] + b[m][l]·u + c[m][l]·v ≥ 0
/// for m = 0..3 (m = 0: edge AB, ∝ barycentric of C; 1: BC, ∝ A; 2: CA, ∝ B; 3: the plane, t ≤ 1).
struct LineBatch {
  alignas(64) float a[4][kLanes];
  alignas(64) float b[4][kLanes];
  alignas(64) float c[4][kLanes];
  // Row-span form (grid_k > 0 in setup_batch), computed 16 lanes at once: line m at sample
  // (i, j) is al[m] + b[m]·i + c[m]·j ≥ 0, i.e. i ≥ t (b > 0) or i ≤ t (b < 0) with
  // t = (al[m] + c[m]·j)·inv[m]. Adding lo_off (0 where b > 0, −∞ elsewhere) or hi_off (0 where
  // b < 0, +∞ elsewhere) to t makes each line a lower or an upper bound without a branch.
  alignas(64) float al[4][kLanes];
  alignas(64) float inv[4][kLanes];  // −1/b[m], 0 where b[m] = 0
  alignas(64) float lo_off[4][kLanes];
  alignas(64) float hi_off[4][kLanes];
  ShadowCells cells;  // setup_batch with grid_k > 0
};

/// Batched setup of candidates [first, first+16) (SIMD across triangles: the per-triangle setup
/// dominates a scalar rasterizer). Returns the lanes whose lines can all be non-negative inside the
/// sample bounding box [uv_lo, uv_hi] — the exact "P is in the triangle's shadow volume" test for
/// that box; the others are rejected without rasterization. grid_k > 0: the samples are the
/// regular grid_k × grid_k cell centres; the row-span form is filled in, and a triangle whose
/// shadow's bounding box holds no sample centre is rejected too.
uint32_t setup_batch(const CandidateBatch& batch, int first, const PixelLight& light, Vec2 uv_lo,
                     Vec2 uv_hi, int grid_k, LineBatch& out);

/// The lanes of `lanes` whose shadow box (ShadowCells) holds only samples already set in
/// the pixel's rows (the boxes are clamped to its k × k grid): rasterizing them could add no bit
/// (on closed meshes, the back faces behind front faces rasterized before them), and a semi-opaque
/// one would only darken samples already blocked, which shading ignores. Boxes over three rows tall
/// are never hidden. `rows` must hold 32 entries (read as two registers).
uint32_t hidden_lanes(const ShadowCells& cells, uint32_t lanes, const uint32_t* rows);

/// Row-span rasterization onto the regular k×k grid of cell centres (k ≤ 32; `lines` set up with
/// grid_k = k): row j's covered samples form one interval, one machine word per row. Writes the
/// triangle's coverage to rows[0..k) (and zeros up to the next multiple of 16: size rows for that);
/// returns the set of non-empty rows (0: no sample covered).
uint32_t raster_rows(const LineBatch& lines, int lane, int k, uint32_t* rows);

/// raster_rows for several opaque triangles (bit l of `lanes`: lane l), OR-ed into rows[0..k)
/// (size as for raster_rows) without a branch on coverage; returns the lanes that cover a sample.
/// Lanes whose shadow box (lines.cells) is a few rows tall go row by row, 16 triangles at once,
/// over their boxes' rows only; the bits are those of raster_rows.
uint32_t raster_rows_or(const LineBatch& lines, uint32_t lanes, int k, uint32_t* rows);

/// Per-sample rasterization (any sample positions: irregular patterns, point lights, k > 32):
/// coverage bit s of words[] for sample (u[s], v[s]). Returns true when some sample is covered.
bool raster_samples(const LineBatch& lines, int lane, const float* u, const float* v, int n,
                    uint64_t* words);

/// Barycentrics (Embree's convention: u weights vertex 1, v vertex 2) of the hit of the ray toward
/// light uv (su, sv), from the edge lines.
inline Vec2 hit_barycentrics(const LineBatch& l, int lane, float su, float sv) {
  const float e0 = l.a[0][lane] + l.b[0][lane] * su + l.c[0][lane] * sv;  // ∝ λ_C
  const float e1 = l.a[1][lane] + l.b[1][lane] * su + l.c[1][lane] * sv;  // ∝ λ_A
  const float e2 = l.a[2][lane] + l.b[2][lane] * su + l.c[2][lane] * sv;  // ∝ λ_B
  const float sum = e0 + e1 + e2;
  return sum > 0.0f ? Vec2(e2 / sum, e0 / sum) : Vec2(0.0f);
}

/// Rows of k bits (row-major samples) into 64-bit mask words (SampleMasks layout), OR-ed in.
void rows_to_words(const uint32_t* rows, int k, uint64_t* words);

}  // namespace penumbra::gears
