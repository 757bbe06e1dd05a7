// GEARS step 4 kernels [Wang 2014 §4.2], compiled once per SIMD target (Highway's foreach_target
// re-includes this file) and dispatched at run time (core/simd.hpp). A batch is kLanes = 16
// triangles; each target walks it in registers of W lanes (16 with AVX-512, 8 with AVX2, 4
// otherwise), so every target computes the same float operations lane by lane and returns the
// same bits.
#include "penumbra/shadows/gears/raster.hpp"

#include <algorithm>
#include <array>
#include <bit>
#include <cstddef>
#include <cstring>

#include "penumbra/shadows/gears/solids.hpp"
#include "penumbra/shadows/method.hpp"

#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "penumbra/shadows/gears/raster.cpp"
#include <hwy/foreach_target.h>  // IWYU pragma: keep
#include <hwy/highway.h>

// The vector helpers below are internal (and inlined); GCC warns that passing vectors wider than
// the baseline's by value would change an ABI nobody outside this file uses.
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic ignored "-Wpsabi"
#endif

HWY_BEFORE_NAMESPACE();
namespace penumbra::gears::HWY_NAMESPACE {

#undef PENUMBRA_GEARS_AVX3
#undef PENUMBRA_GEARS_AVX2
#undef PENUMBRA_GEARS_SSE
#if HWY_TARGET == HWY_AVX3 || HWY_TARGET == HWY_AVX3_DL
#define PENUMBRA_GEARS_AVX3 1
constexpr int W = 16;
#elif HWY_TARGET == HWY_AVX2
#define PENUMBRA_GEARS_AVX2 1
constexpr int W = 8;
#elif HWY_TARGET == HWY_SSE4 || HWY_TARGET == HWY_SSSE3
#define PENUMBRA_GEARS_SSE 1
constexpr int W = 4;
#else
constexpr int W = 4;
#endif
static_assert(kLanes % W == 0);

namespace {

constexpr float kTieMargin = static_cast<float>(1.0 - kShadowSegmentEnd);
constexpr uint32_t kRegisterLanes = (1u << W) - 1u;

// GCC/Clang vector extensions of this target's register width: the arithmetic needs no
// intrinsics, and a register never spills into halves (16-lane vectors on an AVX2 target did:
// their lowering went through the stack and ran ~10× slower than AVX-512).
typedef float vf __attribute__((vector_size(W * 4)));
typedef int32_t vi __attribute__((vector_size(W * 4)));
typedef uint32_t vu __attribute__((vector_size(W * 4)));

alignas(64) constexpr int32_t kIota[16] = {0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15};
template <class V, class T>
inline V load_as(const T* p) {
  V r;
  std::memcpy(&r, p, sizeof(r));
  return r;
}
inline vf load(const float* p) {
  return load_as<vf>(p);
}
inline vi loadi(const int32_t* p) {
  return load_as<vi>(p);
}
inline void store(float* p, vf v) {
  std::memcpy(p, &v, sizeof(v));
}
inline void storei(int32_t* p, vi v) {
  std::memcpy(p, &v, sizeof(v));
}
inline vf splat(float x) {
  return vf{} + x;
}
inline vi splati(int32_t x) {
  return vi{} + x;
}
inline vf vmax(vf a, vf b) {
  return a > b ? a : b;
}
inline vf vmin(vf a, vf b) {
  return a < b ? a : b;
}
inline vi iota() {
  return loadi(kIota);
}

/// Bit l of the result: lane l of the comparison-style vector m (−1 or 0) is set.
inline uint32_t movemask(vi m) {
#if PENUMBRA_GEARS_AVX3
  __m512i x;
  std::memcpy(&x, &m, sizeof(x));
  return _mm512_movepi32_mask(x);
#elif PENUMBRA_GEARS_AVX2
  __m256 x;
  std::memcpy(&x, &m, sizeof(x));
  return static_cast<uint32_t>(_mm256_movemask_ps(x));
#elif PENUMBRA_GEARS_SSE
  __m128 x;
  std::memcpy(&x, &m, sizeof(x));
  return static_cast<uint32_t>(_mm_movemask_ps(x));
#else
  uint32_t bits = 0;
  for (int l = 0; l < W; ++l) bits |= static_cast<uint32_t>(m[l] != 0) << l;
  return bits;
#endif
}

/// Lanes l of register h (lanes h … h + W − 1 of a 16-lane batch) below `live` batch lanes.
inline uint32_t live_lanes(int live) {
  return live >= W ? kRegisterLanes : live <= 0 ? 0u : (1u << live) - 1u;
}

/// floor(y) for y ≥ −40 (after clamping), as exact integers in a float-free vector.
inline vi floor_small(vf y) {
  return __builtin_convertvector(y + 64.0f, vi) - 64;
}

/// The vertices of batch lanes [first, first + W) relative to the pixel point p: ax ay az bx … cz.
inline void relative_vertices(const CandidateBatch& batch, int first, vf px, vf py, vf pz,
                              vf r[9]) {
  for (int c = 0; c < 9; ++c)
    r[c] = load(&batch.v[c][first]) - (c % 3 == 0 ? px : c % 3 == 1 ? py : pz);
}

/// Separating-axis completion of the setup for the common case: all three vertices (a, b, c,
/// relative to the pixel point p) between the light plane and p (−p.z < a.z < 0). The triangle's
/// shadow on the light is then the triangle of its vertices' projections from p, so its uv bounds
/// must overlap the sample box [uv_lo, uv_hi] — and, with grid_k > 0, hold a sample centre. False
/// only where that fails; lanes not between pass. Shared by setup_batch and the per-pixel cull
/// (keep), which must compute bit-identical decisions. `cells` gets lanes h … h + W − 1 of the
/// boxes (its `boxed` bits OR-ed in: the caller clears them per batch).
inline vi shadow_box_holds_samples(const vf r[9], vf px, vf py, vf pzv, Vec2 uv_lo, Vec2 uv_hi,
                                   int grid_k, ShadowCells* cells, int h) {
  const vf ax = r[0], ay = r[1], az = r[2], bx = r[3], by = r[4], bz = r[5], cx = r[6], cy = r[7],
           cz = r[8];
  const vi between =
      (az < 0.0f) & (az > -pzv) & (bz < 0.0f) & (bz > -pzv) & (cz < 0.0f) & (cz > -pzv);
  const vf ta = pzv / -az, tb = pzv / -bz, tc = pzv / -cz;
  const vf ua = px + ax * ta, ub = px + bx * tb, uc = px + cx * tc;
  const vf va = py + ay * ta, vb = py + by * tb, vc = py + cy * tc;
  const vf u0 = vmin(vmin(ua, ub), uc), u1 = vmax(vmax(ua, ub), uc);
  const vf v0 = vmin(vmin(va, vb), vc), v1 = vmax(vmax(va, vb), vc);
  vi overlap = (u0 <= uv_hi.x) & (u1 >= uv_lo.x) & (v0 <= uv_hi.y) & (v1 >= uv_lo.y);
  if (grid_k > 0) {
    // Some sample centre ((i + ½)/k, (j + ½)/k) must lie in that bounding box: small shadows
    // often fall between rows or columns. Widened by 10⁻⁴ light widths (far above the rounding
    // of the projections), so the rasterizer still decides every sample near an edge.
    const float kf = static_cast<float>(grid_k), slack = 1e-4f * kf;
    const vf lim_lo = splat(-2.0f), lim_hi = splat(kf + 1.0f);
    auto first_centre = [&](vf x) {  // ceil(k·x − ½ − slack), clamped to [−2, k + 1]
      return -floor_small(-vmin(vmax(kf * x - 0.5f - slack, lim_lo), lim_hi));
    };
    auto last_centre = [&](vf x) {  // floor(k·x − ½ + slack), clamped to [−2, k + 1]
      return floor_small(vmin(vmax(kf * x - 0.5f + slack, lim_lo), lim_hi));
    };
    const vi i0 = first_centre(u0), i1 = last_centre(u1);
    const vi j0 = first_centre(v0), j1 = last_centre(v1);
    const vi top = splati(grid_k - 1), zero = splati(0);
    const vi ci0 = i0 > zero ? i0 : zero, ci1 = i1 < top ? i1 : top;
    const vi cj0 = j0 > zero ? j0 : zero, cj1 = j1 < top ? j1 : top;
    overlap &= (ci0 <= ci1) & (cj0 <= cj1);
    if (cells != nullptr) {
      storei(cells->box[0] + h, ci0);
      storei(cells->box[1] + h, ci1);
      storei(cells->box[2] + h, cj0);
      storei(cells->box[3] + h, cj1);
      cells->boxed |= movemask(between & overlap) << h;
    }
  }
  return overlap | ~between;
}

/// The lanes whose triangle's solid (kNoSolid: none) is one of `outside`'s bits.
inline vi solid_lanes(const uint32_t* solid, uint64_t outside) {
  const vi s = load_as<vi>(solid);
  const vi low = splati(static_cast<int32_t>(static_cast<uint32_t>(outside)));
  const vi high = splati(static_cast<int32_t>(static_cast<uint32_t>(outside >> 32)));
  const vi word = s < 32 ? low : s < kMaxSolids ? high : vi{};
  return ((word >> (s & 31)) & 1) != 0;
}

// Compression tables (Highway's own compress copies its table onto the stack on every call with
// this compiler). Entry m: the source lanes of m's set bits, in order.
#if PENUMBRA_GEARS_AVX2
// 3-bit lane indices, one per nibble.
constexpr std::array<uint32_t, 256> kCompressNibbles = [] {
  std::array<uint32_t, 256> table{};
  for (uint32_t m = 0; m < 256; ++m) {
    int out = 0;
    for (uint32_t l = 0; l < 8; ++l)
      if (m >> l & 1) table[m] |= l << (4 * out++);
  }
  return table;
}();
#elif PENUMBRA_GEARS_SSE
// pshufb byte indices.
alignas(16) constexpr std::array<std::array<uint8_t, 16>, 16> kCompressBytes = [] {
  std::array<std::array<uint8_t, 16>, 16> table{};
  for (uint32_t m = 0; m < 16; ++m) {
    int out = 0;
    for (uint32_t l = 0; l < 4; ++l)
      if (m >> l & 1) {
        for (uint32_t b = 0; b < 4; ++b) table[m][4 * out + b] = static_cast<uint8_t>(4 * l + b);
        ++out;
      }
  }
  return table;
}();
#endif

/// Lanes `m` (W bits) of src[0, W) to to[at...], in order (4-byte elements: floats, ids, flags);
/// returns how many. May write up to W lanes from `at` (the arrays keep 2 × 16 spare lanes; later
/// lanes overwrite the tail).
template <class T>
inline int compress_register(T* to, int at, const T* src, uint32_t m) {
  static_assert(sizeof(T) == 4);
#if PENUMBRA_GEARS_AVX3
  // Compress in a register, then one full store: the masked compress-store to memory is several
  // times slower.
  _mm512_storeu_si512(
      to + at, _mm512_maskz_compress_epi32(static_cast<__mmask16>(m), _mm512_loadu_si512(src)));
#elif PENUMBRA_GEARS_AVX2
  // A lane permutation from a table, one full store.
  const __m256i nibbles = _mm256_set1_epi32(static_cast<int32_t>(kCompressNibbles[m]));
  const __m256i index =
      _mm256_and_si256(_mm256_srlv_epi32(nibbles, _mm256_setr_epi32(0, 4, 8, 12, 16, 20, 24, 28)),
                       _mm256_set1_epi32(7));
  _mm256_storeu_si256(reinterpret_cast<__m256i*>(to + at),
                      _mm256_permutevar8x32_epi32(
                          _mm256_loadu_si256(reinterpret_cast<const __m256i*>(src)), index));
#elif PENUMBRA_GEARS_SSE
  _mm_storeu_si128(
      reinterpret_cast<__m128i*>(to + at),
      _mm_shuffle_epi8(_mm_loadu_si128(reinterpret_cast<const __m128i*>(src)),
                       _mm_load_si128(reinterpret_cast<const __m128i*>(kCompressBytes[m].data()))));
#else
  int n = at;
  for (uint32_t l = m; l; l &= l - 1) to[n++] = src[std::countr_zero(l)];
#endif
  return std::popcount(m);
}

/// Lanes `m` (16 bits) of src[first, first + 16) to to[at...], in order; returns the new end.
template <class T>
inline int compress_lanes(T* to, int at, const T* src, int first, uint32_t m) {
  for (int h = 0; h < kLanes; h += W)
    at += compress_register(to, at, src + first + h, (m >> h) & kRegisterLanes);
  return at;
}

/// Appends lanes `m` of from[first, first + 16) (every array) at to.count. `to` may be `from`
/// itself when to.count ≤ first: each register is read before the stores that reach it.
void append_lanes(CandidateBatch& to, const CandidateBatch& from, int first, uint32_t m) {
  if (m == 0) return;
  const int at = to.count;
  for (int c = 0; c < 9; ++c) compress_lanes(to.v[c].data(), at, from.v[c].data(), first, m);
  for (auto [dst, src] : {std::pair{&to.zmin, &from.zmin},
                          {&to.hx0, &from.hx0},
                          {&to.hx1, &from.hx1},
                          {&to.hy0, &from.hy0},
                          {&to.hy1, &from.hy1},
                          {&to.nx, &from.nx},
                          {&to.ny, &from.ny},
                          {&to.nz, &from.nz},
                          {&to.nd, &from.nd},
                          {&to.n1, &from.n1},
                          {&to.lmin, &from.lmin},
                          {&to.lmax, &from.lmax}})
    compress_lanes(dst->data(), at, src->data(), first, m);
  compress_lanes(to.tri.data(), at, from.tri.data(), first, m);
  compress_lanes(to.opaque.data(), at, from.opaque.data(), first, m);
  compress_lanes(to.solid.data(), at, from.solid.data(), first, m);
  to.count += std::popcount(m);
}

#if PENUMBRA_GEARS_AVX3
/// 16 × 16 transpose of 32-bit elements: on return, lane i of row[j] is element j of input row i
/// (unpacks of 32- and 64-bit elements, then two rounds of 128-bit block shuffles).
inline void transpose16(__m512i row[16]) {
  __m512i t[16];
  for (int i = 0; i < 16; i += 2) {
    t[i] = _mm512_unpacklo_epi32(row[i], row[i + 1]);
    t[i + 1] = _mm512_unpackhi_epi32(row[i], row[i + 1]);
  }
  for (int i = 0; i < 16; i += 4)
    for (int h = 0; h < 2; ++h) {
      row[i + 2 * h] = _mm512_unpacklo_epi64(t[i + h], t[i + 2 + h]);
      row[i + 2 * h + 1] = _mm512_unpackhi_epi64(t[i + h], t[i + 2 + h]);
    }
  // Now row[4g + e], block b: element 4b + e of rows 4g … 4g + 3; the 4 × 4 blocks remain.
  for (int i = 0; i < 16; i += 8)
    for (int h = 0; h < 4; ++h) {
      t[i + h] = _mm512_shuffle_i32x4(row[i + h], row[i + 4 + h], 0x88);      // blocks 0, 2
      t[i + 4 + h] = _mm512_shuffle_i32x4(row[i + h], row[i + 4 + h], 0xdd);  // blocks 1, 3
    }
  for (int h = 0; h < 8; ++h) {
    row[h] = _mm512_shuffle_i32x4(t[h], t[8 + h], 0x88);
    row[8 + h] = _mm512_shuffle_i32x4(t[h], t[8 + h], 0xdd);
  }
}
#endif

}  // namespace

/// CandidateBatch::gather's loop, after its depth cut and reserve: the pairs [begin, end) that may
/// block one of the item's samples, appended to `to` from its first lane.
void gather_kernel(CandidateBatch& to, const PackedTriangle* tris, const TrianglePlane* planes,
                   const CellPair* begin, const CellPair* end, const ItemBounds& item) {
  int count = 0;
  // The list is in depth order, its triangles scattered through `tris`: the loads miss the cache
  // and the loop's few instructions cannot hide that, so the lines are prefetched well ahead.
  constexpr std::ptrdiff_t kAhead = 16;
  const CellPair* pair = begin;
#if PENUMBRA_GEARS_AVX3
  // 16 triangles at a time: one cache line each into a register, transposed into the 16 fields'
  // lanes, tested together and compressed into the arrays (one store per field and 16 triangles
  // instead of one per field and triangle).
  static_assert(sizeof(PackedTriangle) == 64 && offsetof(PackedTriangle, zmin) == 36 &&
                offsetof(PackedTriangle, solid) == 60);
  const __m512 zmax = _mm512_set1_ps(item.zmax), ix0 = _mm512_set1_ps(item.ix0),
               ix1 = _mm512_set1_ps(item.ix1), iy0 = _mm512_set1_ps(item.iy0),
               iy1 = _mm512_set1_ps(item.iy1);
  for (; end - pair >= kLanes; pair += kLanes) {
    __m512i row[16];
    alignas(64) uint32_t id[kLanes];
    for (int l = 0; l < kLanes; ++l) {
      if (end - pair > kAhead + l) __builtin_prefetch(&tris[pair[kAhead + l].item]);
      id[l] = pair[l].item;
      row[l] = _mm512_load_si512(&tris[id[l]]);
    }
    transpose16(row);
    auto f = [&](int field) { return _mm512_castsi512_ps(row[field]); };
    const __mmask16 m =
        _mm512_cmp_ps_mask(f(9), zmax, _CMP_LE_OQ) & _mm512_cmp_ps_mask(ix0, f(10), _CMP_LE_OQ) &
        _mm512_cmp_ps_mask(ix1, f(11), _CMP_GE_OQ) & _mm512_cmp_ps_mask(iy0, f(12), _CMP_LE_OQ) &
        _mm512_cmp_ps_mask(iy1, f(13), _CMP_GE_OQ);
    if (m == 0) continue;
    auto put = [&](auto* dst, __m512i x) {
      _mm512_storeu_si512(dst + count, _mm512_maskz_compress_epi32(m, x));
    };
    for (int c = 0; c < 9; ++c) put(to.v[c].data(), row[c]);
    put(to.zmin.data(), row[9]);
    put(to.hx0.data(), row[10]);
    put(to.hx1.data(), row[11]);
    put(to.hy0.data(), row[12]);
    put(to.hy1.data(), row[13]);
    put(to.opaque.data(), row[14]);
    put(to.solid.data(), row[15]);
    put(to.tri.data(), _mm512_load_si512(id));
    count += std::popcount(static_cast<uint32_t>(m));
  }
#endif
  // Branch-free compaction: every pair is written, only the kept ones advance `count` (the test
  // is unpredictable, the copy is one cache line).
  for (; pair != end; ++pair) {
    if (end - pair > kAhead) __builtin_prefetch(&tris[pair[kAhead].item]);
    const uint32_t t = pair->item;
    const PackedTriangle& p = tris[t];
    const int i = count;
    to.tri[i] = t;
    for (int c = 0; c < 9; ++c) to.v[c][i] = p.v[c];
    to.zmin[i] = p.zmin, to.hx0[i] = p.hx0, to.hx1[i] = p.hx1, to.hy0[i] = p.hy0, to.hy1[i] = p.hy1;
    to.opaque[i] = p.opaque;
    to.solid[i] = p.solid;
    count += may_block(p, item);
  }
  // Planes only for the kept ones (a second cache line per triangle, read once per item).
  for (int i = 0; i < count; ++i) {
    if (i + kAhead < count) __builtin_prefetch(&planes[to.tri[i + kAhead]]);
    const TrianglePlane& q = planes[to.tri[i]];
    to.nx[i] = q.nx, to.ny[i] = q.ny, to.nz[i] = q.nz, to.nd[i] = q.d, to.n1[i] = q.n1;
    to.lmin[i] = q.lmin, to.lmax[i] = q.lmax;
  }
  to.count = count;
}

/// CandidateBatch::narrow's loop over from[0, end), after its reserve.
void narrow_kernel(CandidateBatch& to, const CandidateBatch& from, int end, const ItemBounds& group,
                   const Vec3* points, int point_count, uint64_t outside) {
  to.count = 0;
  for (int first = 0; first < end; first += kLanes) {
    uint32_t m = 0;
    for (int h = 0; h < kLanes; h += W) {
      const int f = first + h;
      vi kept = (iota() + f < end) & (splat(group.ix0) <= load(&from.hx0[f])) &
                (splat(group.ix1) >= load(&from.hx1[f])) &
                (splat(group.iy0) <= load(&from.hy0[f])) & (splat(group.iy1) >= load(&from.hy1[f]));
      if (point_count > 0 && movemask(kept) != 0) {
        const vf nxv = load(&from.nx[f]), nyv = load(&from.ny[f]), nzv = load(&from.nz[f]),
                 d = load(&from.nd[f]);
        const vf n1 = load(&from.n1[f]), abs_d = vmax(d, -d);
        vi all_above = kept, all_below = kept;
        for (int i = 0; i < point_count; ++i) {
          const Vec3& q = points[i];
          const float q_inf = std::max({std::abs(q.x), std::abs(q.y), std::abs(q.z)});
          const vf side = nxv * q.x + nyv * q.y + nzv * q.z - d;
          const vf tol = (2.0f * kPlaneRel) * (n1 * q_inf + abs_d);
          all_above &= side > tol;
          all_below &= side < -tol;
        }
        kept &=
            ~((all_above & (load(&from.lmin[f]) > 0.0f)) |
              (all_below & ((load(&from.lmax[f]) < 0.0f) | solid_lanes(&from.solid[f], outside))));
      }
      m |= movemask(kept) << h;
    }
    append_lanes(to, from, first, m);
  }
}

/// CandidateBatch::drop_solid_back_faces's in-place compaction (samples.outside ≠ 0).
void drop_solid_back_faces_kernel(CandidateBatch& batch, const SampleBox& samples) {
  float box_inf = 0.0f;
  for (int a = 0; a < 3; ++a)
    box_inf = std::max({box_inf, std::abs(samples.lo[a]), std::abs(samples.hi[a])});
  const int end = batch.count;
  batch.count = 0;  // compacted in place: lanes are read before the stores that reach them
  for (int first = 0; first < end; first += kLanes) {
    uint32_t m = 0;
    for (int h = 0; h < kLanes; h += W) {
      const int f = first + h;
      // The most positive side over the box: every sample strictly behind this face of a solid
      // they all lie outside of (keep()'s test, at twice its tolerance for the whole box).
      const vf nxv = load(&batch.nx[f]), nyv = load(&batch.ny[f]), nzv = load(&batch.nz[f]);
      const vf d = load(&batch.nd[f]);
      const vf most = vmax(nxv * samples.lo.x, nxv * samples.hi.x) +
                      vmax(nyv * samples.lo.y, nyv * samples.hi.y) +
                      vmax(nzv * samples.lo.z, nzv * samples.hi.z) - d;
      const vf tol = (2.0f * kPlaneRel) * (load(&batch.n1[f]) * box_inf + vmax(d, -d));
      const vi behind = (most < -tol) & solid_lanes(&batch.solid[f], samples.outside);
      m |= movemask((iota() + f < end) & ~behind) << h;
    }
    append_lanes(batch, batch, first, m);
  }
}

/// The rows j of `rows` (32 entries), lane by lane (indices taken mod 32).
inline vu rows_at(const uint32_t* rows, vu row) {
  const vi j = __builtin_convertvector(row & 31u, vi);
#if PENUMBRA_GEARS_AVX3
  // A two-register permute: gathers are several times slower on AVX-512 hardware and took a
  // quarter of keep()'s time.
  __m512i lo, hi, idx;
  std::memcpy(&lo, rows, sizeof(lo));
  std::memcpy(&hi, rows + 16, sizeof(hi));
  std::memcpy(&idx, &j, sizeof(idx));
  const __m512i g = _mm512_permutex2var_epi32(lo, idx, hi);
  vu r;
  std::memcpy(&r, &g, sizeof(r));
  return r;
#elif PENUMBRA_GEARS_AVX2
  __m256i idx;
  std::memcpy(&idx, &j, sizeof(idx));
  const __m256i g = _mm256_i32gather_epi32(reinterpret_cast<const int*>(rows), idx, 4);
  vu r;
  std::memcpy(&r, &g, sizeof(r));
  return r;
#else
  vu r;
  for (int l = 0; l < W; ++l) r[l] = rows[j[l]];
  return r;
#endif
}

/// hidden_lanes for lanes h … h + W − 1 (their bits of `lanes`, at 0).
inline uint32_t hidden_register(const ShadowCells& cells, int h, uint32_t lanes,
                                const uint32_t* rows) {
  const vi i0 = loadi(cells.box[0] + h), i1 = loadi(cells.box[1] + h);
  // Unsigned: lanes outside `lanes` hold whatever the cells held (their results are masked off),
  // and unsigned arithmetic cannot overflow on them; valid boxes lie in [0, k).
  const vu j0 = load_as<vu>(cells.box[2] + h), j1 = load_as<vu>(cells.box[3] + h);
  // Bits i0 … i1 of a row (i1 ≤ 31: 2 << 31 wraps to 0, as in span_bits).
  const vu need = ((vu{} + 2u) << (__builtin_convertvector(i1, vu) & 31u)) -
                  ((vu{} + 1u) << (__builtin_convertvector(i0, vu) & 31u));
  // Shadows of dense meshes span a row or two: rows j0, j0 + 1 and j1 cover boxes of up to three
  // rows, read W lanes at once; taller boxes are never called hidden (they are rasterized).
  const vu j_mid = j0 + 1u < j1 ? j0 + 1u : j1;
  const vu blocked = rows_at(rows, j0) & rows_at(rows, j_mid) & rows_at(rows, j1);
  const vi hidden = ((blocked & need) == need) & (j1 - j0 <= 2u);
  return movemask(hidden) & lanes;
}

uint32_t hidden_lanes_kernel(const ShadowCells& cells, uint32_t lanes, const uint32_t* rows) {
  lanes &= cells.boxed;
  uint32_t hidden = 0;
  for (int h = 0; h < kLanes && (lanes >> h) != 0; h += W)
    hidden |= hidden_register(cells, h, (lanes >> h) & kRegisterLanes, rows) << h;
  return hidden;
}

/// CandidateBatch::keep's loop, after its reserve.
void keep_kernel(CandidateBatch& to, const CandidateBatch& from, int begin, int end,
                 const ItemBounds& bounds, const Vec3& p, const ShadowBoxCull* box,
                 const uint32_t* rows, uint64_t outside) {
  ShadowCells cells;
  ShadowCells* want_cells = rows != nullptr && box != nullptr && box->grid_k > 0 ? &cells : nullptr;
  to.count = 0;
  const vf px = splat(p.x), py = splat(p.y), pz = splat(p.z);
  const vf p_inf = splat(std::max({std::abs(p.x), std::abs(p.y), std::abs(p.z)}));
  for (int first = begin; first < end; first += kLanes) {
    uint32_t m = 0;
    cells.boxed = 0;
    for (int h = 0; h < kLanes; h += W) {
      const int f = first + h;
      // may_block() on W lanes (padding lanes fail the depth cut), within [begin, end).
      vi kept =
          (iota() + f < end) & (load(&from.zmin[f]) <= splat(bounds.zmax)) &
          (splat(bounds.ix0) <= load(&from.hx0[f])) & (splat(bounds.ix1) >= load(&from.hx1[f])) &
          (splat(bounds.iy0) <= load(&from.hy0[f])) & (splat(bounds.iy1) >= load(&from.hy1[f]));
      // Separating plane: P and every light corner strictly on one side of T's plane.
      const vf d = load(&from.nd[f]);
      const vf side = load(&from.nx[f]) * px + load(&from.ny[f]) * py + load(&from.nz[f]) * pz - d;
      const vf tol = kPlaneRel * (load(&from.n1[f]) * p_inf + vmax(d, -d));
      // And a face of a solid the sample lies outside of, seen strictly from behind.
      kept &= ~(
          ((side > tol) & (load(&from.lmin[f]) > 0.0f)) |
          ((side < -tol) & ((load(&from.lmax[f]) < 0.0f) | solid_lanes(&from.solid[f], outside))));
      if (box != nullptr && movemask(kept) != 0) {
        // setup_batch's shadow-box test, moved ahead of it with the same arithmetic: it rejects
        // the same triangles, only before their edge planes are built (dense meshes: most).
        vf r[9];
        relative_vertices(from, f, px, py, pz, r);
        kept &= shadow_box_holds_samples(r, px, py, pz, box->uv_lo, box->uv_hi, box->grid_k,
                                         want_cells, h);
      }
      m |= movemask(kept) << h;
    }
    if (want_cells != nullptr && m != 0) m &= ~hidden_lanes_kernel(cells, m, rows);
    if (m == 0) continue;
    for (int c = 0; c < 9; ++c)
      compress_lanes(to.v[c].data(), to.count, from.v[c].data(), first, m);
    compress_lanes(to.tri.data(), to.count, from.tri.data(), first, m);
    compress_lanes(to.opaque.data(), to.count, from.opaque.data(), first, m);
    to.count += std::popcount(m);
  }
}

/// setup_batch for lanes first + h … first + h + W − 1; returns their W bits.
uint32_t setup_register(const CandidateBatch& batch, int first, int h, const PixelLight& light,
                        Vec2 uv_lo, Vec2 uv_hi, int grid_k, LineBatch& out) {
  const vf px = splat(light.p.x), py = splat(light.p.y), pz = splat(light.p.z);
  // Vertices relative to the pixel point.
  vf r[9];
  relative_vertices(batch, first + h, px, py, pz, r);
  const vf ax = r[0], ay = r[1], az = r[2], bx = r[3], by = r[4], bz = r[5], cx = r[6], cy = r[7],
           cz = r[8];
  // Edge-plane normals n0 = a×b, n1 = b×c, n2 = c×a [Wang 2014 §4.2: "an edge plane is defined by a
  // triangle edge and the eye of the camera that computes the bitmask"].
  // Each is computed from its two vertices in a canonical order (lexicographic) and then signed
  // for this triangle's traversal, so the two triangles sharing an edge get exactly opposite
  // lines: a sample on either side of it is covered by one of them, never by neither (the
  // rasterization is watertight, as Embree's ray test is).
  vf nx[3], ny[3], nz[3], sign[3];
  const vf* const vx[3] = {&ax, &bx, &cx};
  const vf* const vy[3] = {&ay, &by, &cy};
  const vf* const vz[3] = {&az, &bz, &cz};
  for (int m = 0; m < 3; ++m) {
    const int e0 = m, e1 = (m + 1) % 3;
    const vf ux = *vx[e0], uy = *vy[e0], uz = *vz[e0], wx = *vx[e1], wy = *vy[e1], wz = *vz[e1];
    const vi before =
        (ux < wx) | ((ux == wx) & ((uy < wy) | ((uy == wy) & (uz <= wz))));  // u first
    const vf px0 = before ? ux : wx, py0 = before ? uy : wy, pz0 = before ? uz : wz;
    const vf px1 = before ? wx : ux, py1 = before ? wy : uy, pz1 = before ? wz : uz;
    nx[m] = py0 * pz1 - pz0 * py1, ny[m] = pz0 * px1 - px0 * pz1, nz[m] = px0 * py1 - py0 * px1;
    sign[m] = before ? splat(1.0f) : splat(-1.0f);
  }
  const vf det = sign[1] * (ax * nx[1] + ay * ny[1] + az * nz[1]);  // a · (b × c)
  const vf s = det > 0.0f ? splat(1.0f) : splat(-1.0f);
  vi ok = det != 0.0f;
  vf A[4], B[4], C[4];
  for (int m = 0; m < 3; ++m) {
    const vf sm = s * sign[m];
    if (light.axis_aligned) {
      // X − P = w + (u, v, 0).
      A[m] = sm * (nx[m] * light.w.x + ny[m] * light.w.y + nz[m] * light.w.z);
      B[m] = sm * nx[m];
      C[m] = sm * ny[m];
    } else {
      A[m] = sm * (nx[m] * light.w.x + ny[m] * light.w.y + nz[m] * light.w.z);
      B[m] = sm * (nx[m] * light.eu.x + ny[m] * light.eu.y + nz[m] * light.eu.z);
      C[m] = sm * (nx[m] * light.ev.x + ny[m] * light.ev.y + nz[m] * light.ev.z);
    }
  }
  // The plane: the segment reaches the triangle (t ≤ 1) iff Σ s·e_i(X) ≥ |det|, i.e.
  // s·N·(X − A) ≥ 0 with N = Σ n_i = (b − a) × (c − a). Evaluated in that second form: Σ s·e_i and
  // det are both of order |a|·|b|·|X − P| and cancel for a light point on the triangle's plane,
  // which made the tie salt-and-pepper. The tie rule (shadows/method.hpp): the light point must be
  // beyond the plane by (1 − kShadowSegmentEnd)·|X − P|, so a face through it never blocks.
  const vf ux = bx - ax, uy = by - ay, uz = bz - az, wx = cx - ax, wy = cy - ay, wz = cz - az;
  const vf Nx = uy * wz - uz * wy, Ny = uz * wx - ux * wz, Nz = ux * wy - uy * wx;
  const Vec3 reach = light.w + 0.5f * (light.eu + light.ev);       // P to the light centre
  const vf norm1 = vmax(Nx, -Nx) + vmax(Ny, -Ny) + vmax(Nz, -Nz);  // |N| ≤ norm1 ≤ √3·|N|
  const vf margin = splat(kTieMargin * glm::length(reach)) * norm1;
  A[3] = s * (Nx * (splat(light.w.x) - ax) + Ny * (splat(light.w.y) - ay) +
              Nz * (splat(light.w.z) - az)) -
         margin;
  B[3] = s * (Nx * light.eu.x + Ny * light.eu.y + Nz * light.eu.z);
  C[3] = s * (Nx * light.ev.x + Ny * light.ev.y + Nz * light.ev.z);
  for (int m = 0; m < 4; ++m) {
    const vf best =
        A[m] + vmax(B[m] * uv_lo.x, B[m] * uv_hi.x) + vmax(C[m] * uv_lo.y, C[m] * uv_hi.y);
    ok &= best >= 0.0f;
    store(out.a[m] + h, A[m]);
    store(out.b[m] + h, B[m]);
    store(out.c[m] + h, C[m]);
  }
  if (light.axis_aligned)
    ok &= shadow_box_holds_samples(r, px, py, pz, uv_lo, uv_hi, grid_k, &out.cells, h);
  const uint32_t result = movemask(ok) & live_lanes(batch.count - first - h);
  if (grid_k > 0 && result != 0) {
    // Row-span form: index space of sample (i, j) at ((i + ½)/k, (j + ½)/k).
    const float kf = static_cast<float>(grid_k);
    for (int m = 0; m < 4; ++m) {
      store(out.al[m] + h, kf * A[m] + 0.5f * (B[m] + C[m]));
      store(out.inv[m] + h, B[m] != 0.0f ? -1.0f / B[m] : splat(0.0f));
      store(out.lo_off[m] + h, B[m] > 0.0f ? splat(0.0f) : splat(-kInfinity));
      store(out.hi_off[m] + h, B[m] < 0.0f ? splat(0.0f) : splat(kInfinity));
    }
  }
  return result;
}

uint32_t setup_batch_kernel(const CandidateBatch& batch, int first, const PixelLight& light,
                            Vec2 uv_lo, Vec2 uv_hi, int grid_k, LineBatch& out) {
  out.cells.boxed = 0;
  uint32_t result = 0;
  for (int h = 0; h < kLanes; h += W)
    result |= setup_register(batch, first, h, light, uv_lo, uv_hi, grid_k, out) << h;
  return result;
}

/// Covered columns lo … hi of W (triangle, row) pairs, element by element: lane l is row j[l] of
/// the triangle whose row-span lines are lane l of al, c, inv, lo_off, hi_off (b: the lines'
/// u slopes, for lines parallel to the rows); `valid` marks non-empty spans. Branch-free over
/// the four lines (their slopes' signs are unpredictable): line m bounds i from below by t
/// (b > 0) or from above (b < 0); the offsets pick which (gears/raster.hpp). Shared by the
/// per-triangle form (W rows of one triangle) and the per-row form (one row of W triangles), so
/// both give the same bits. kFlat: some line may be parallel to the rows (b = 0), all or nothing
/// per row.
struct RowSpans {
  vi lo, hi, valid;
};
template <bool kFlat>
inline RowSpans row_spans(const vf al[4], const vf c[4], const vf inv[4], const vf lo_off[4],
                          const vf hi_off[4], const vf b[4], vf j, int k) {
  const float kf = static_cast<float>(k);
  // Span [ceil(max of lower bounds), floor(min of upper bounds)]: ceil and floor are monotonic,
  // so taking them once after the max/min gives the same integers as taking them per line.
  vf t_lo = splat(-2.0f), t_hi = splat(kf + 1.0f);  // also the clamp, for the conversions
  vi empty = j >= kf;
  for (int m = 0; m < 4; ++m) {
    const vf cj = al[m] + c[m] * j;
    const vf t = cj * inv[m];
    t_lo = vmax(t_lo, t + lo_off[m]);
    t_hi = vmin(t_hi, t + hi_off[m]);
    if constexpr (kFlat) empty |= (b[m] == 0.0f) & (cj < 0.0f);
  }
  const vi lo0 = -floor_small(-vmin(t_lo, splat(kf + 1.0f)));
  const vi hi0 = floor_small(vmax(t_hi, splat(-2.0f)));
  RowSpans out;
  out.lo = lo0 > 0 ? lo0 : splati(0);
  out.hi = hi0 < (k - 1) ? hi0 : splati(k - 1);
  out.valid = (out.lo <= out.hi) & ~empty;
  return out;
}

/// Bits lo … hi of each valid span (hi ≤ 31: 2 << 31 wraps to 0, the full row).
inline vu span_bits(const RowSpans& s) {
  vu mask = (vu{} + 2u) << __builtin_convertvector(s.hi > 0 ? s.hi : splati(0), vu);
  mask -= (vu{} + 1u) << __builtin_convertvector(s.lo < 31 ? s.lo : splati(31), vu);
  return mask & __builtin_convertvector(s.valid, vu);
}

/// Rows jb … jb + W − 1 of triangle `lane`'s coverage (row j: bits lo..hi); `valid_rows` gets the
/// non-empty rows.
inline vu span_rows(const LineBatch& lines, int lane, int k, int jb, uint32_t& valid_rows) {
  vf al[4], c[4], inv[4], lo_off[4], hi_off[4], b[4];
  for (int m = 0; m < 4; ++m) {
    al[m] = splat(lines.al[m][lane]), c[m] = splat(lines.c[m][lane]);
    inv[m] = splat(lines.inv[m][lane]), b[m] = splat(lines.b[m][lane]);
    lo_off[m] = splat(lines.lo_off[m][lane]), hi_off[m] = splat(lines.hi_off[m][lane]);
  }
  // A line parallel to the rows (b = 0) is rare: kept out of the hot path.
  const bool flat = (lines.b[0][lane] == 0.0f) | (lines.b[1][lane] == 0.0f) |
                    (lines.b[2][lane] == 0.0f) | (lines.b[3][lane] == 0.0f);
  const vf j = __builtin_convertvector(iota() + jb, vf);
  const RowSpans s = flat ? row_spans<true>(al, c, inv, lo_off, hi_off, b, j, k)
                          : row_spans<false>(al, c, inv, lo_off, hi_off, b, j, k);
  valid_rows = movemask(s.valid);
  return span_bits(s);
}

/// The lanes of `lanes` whose shadow box (ShadowCells) is at most kShortRows rows tall, where
/// rasterizing them row by row (raster_short_or) costs less than triangle by triangle: a pass
/// over one row of 16 lanes costs about a pass over 16 rows of one lane, so row by row when the
/// lanes outnumber the tallest box's rows (per 16 rows of k).
constexpr int kShortRows = 4;
inline uint32_t short_lanes(const ShadowCells& cells, uint32_t lanes, int k) {
  uint32_t few = 0;
  int tallest = 0;
  for (uint32_t l = cells.boxed & lanes; l; l &= l - 1) {
    const int lane = std::countr_zero(l);
    const int height = cells.box[3][lane] - cells.box[2][lane] + 1;
    if (height <= kShortRows) {
      few |= 1u << lane;
      tallest = std::max(tallest, height);
    }
  }
  // Fixed thresholds of 3, 5, 6 and 8 lanes measured alike on the dense models (k = 16).
  return std::popcount(few) * ((k + kLanes - 1) / kLanes) > tallest ? few : 0;
}

/// raster_rows_or for lanes whose shadow box is at most kShortRows rows tall (dense meshes: most
/// shadows hold one or two sample centres): one row of W triangles at a time, only the rows of
/// their boxes (every covered sample lies in the box), instead of all k rows of each triangle.
uint32_t raster_short_or(const LineBatch& lines, uint32_t lanes, int k, uint32_t* rows) {
  uint32_t hit = 0;
  for (int h = 0; h < kLanes; h += W) {
    const uint32_t mine = (lanes >> h) & kRegisterLanes;
    if (mine == 0) continue;
    vf al[4], c[4], inv[4], lo_off[4], hi_off[4], b[4];
    bool flat = false;
    for (int m = 0; m < 4; ++m) {
      al[m] = load(lines.al[m] + h), c[m] = load(lines.c[m] + h), inv[m] = load(lines.inv[m] + h);
      lo_off[m] = load(lines.lo_off[m] + h), hi_off[m] = load(lines.hi_off[m] + h);
      b[m] = load(lines.b[m] + h);
      flat |= (movemask(b[m] == 0.0f) & mine) != 0;
    }
    // Unsigned, as in hidden_register: lanes outside `mine` hold stale boxes.
    const vu j0 = load_as<vu>(lines.cells.box[2] + h), j1 = load_as<vu>(lines.cells.box[3] + h);
    for (int dj = 0; dj < kShortRows; ++dj) {
      const vu j = j0 + static_cast<uint32_t>(dj);
      const uint32_t live = movemask(j <= j1) & mine;
      if (live == 0) break;
      const vf jf = __builtin_convertvector((vi)j, vf);
      const RowSpans s = flat ? row_spans<true>(al, c, inv, lo_off, hi_off, b, jf, k)
                              : row_spans<false>(al, c, inv, lo_off, hi_off, b, jf, k);
      const uint32_t covered = movemask(s.valid) & live;
      hit |= covered << h;
      alignas(64) uint32_t bits[W];
      alignas(64) uint32_t row[W];
      const vu m = span_bits(s);
      std::memcpy(bits, &m, sizeof(bits));
      std::memcpy(row, &j, sizeof(row));
      for (uint32_t l = covered; l; l &= l - 1) {
        const int lane = std::countr_zero(l);
        rows[row[lane]] |= bits[lane];
      }
    }
  }
  return hit;
}

uint32_t raster_rows_kernel(const LineBatch& lines, int lane, int k, uint32_t* rows) {
  uint32_t any = 0;
  // Whole 16-row blocks: rows j ≥ k are empty, so whole registers can be stored.
  for (int jb = 0; jb < k; jb += kLanes)
    for (int h = 0; h < kLanes; h += W) {
      uint32_t valid;
      const vu mask = span_rows(lines, lane, k, jb + h, valid);
      std::memcpy(rows + jb + h, &mask, sizeof(mask));
      any |= valid << (jb + h);
    }
  return any;
}

uint32_t raster_rows_or_kernel(const LineBatch& lines, uint32_t lanes, int k, uint32_t* rows) {
  const uint32_t few = short_lanes(lines.cells, lanes, k);
  uint32_t hit = few != 0 ? raster_short_or(lines, few, k, rows) : 0;
  lanes &= ~few;
  if (lanes == 0) return hit;
  for (int jb = 0; jb < k; jb += W) {
    vu acc;
    std::memcpy(&acc, rows + jb, sizeof(acc));
    for (uint32_t l = lanes; l; l &= l - 1) {
      const int lane = std::countr_zero(l);
      uint32_t valid;
      acc |= span_rows(lines, lane, k, jb, valid);
      hit |= static_cast<uint32_t>(valid != 0) << lane;
    }
    std::memcpy(rows + jb, &acc, sizeof(acc));
  }
  return hit;
}

bool raster_samples_kernel(const LineBatch& lines, int lane, const float* u, const float* v, int n,
                           uint64_t* words) {
  float a[4], b[4], c[4];
  for (int m = 0; m < 4; ++m)
    a[m] = lines.a[m][lane], b[m] = lines.b[m][lane], c[m] = lines.c[m][lane];
  uint64_t any = 0;
  for (int base = 0; base < n; base += 64) {
    const int cnt = std::min(64, n - base);
    uint64_t bits = 0;
    for (int s = 0; s < cnt; ++s) {
      const float su = u[base + s], sv = v[base + s];
      const bool in = a[0] + b[0] * su + c[0] * sv >= 0.0f &&
                      a[1] + b[1] * su + c[1] * sv >= 0.0f &&
                      a[2] + b[2] * su + c[2] * sv >= 0.0f && a[3] + b[3] * su + c[3] * sv >= 0.0f;
      bits |= static_cast<uint64_t>(in) << s;
    }
    words[base >> 6] = bits;
    any |= bits;
  }
  return any != 0;
}

// NOLINTNEXTLINE(google-readability-namespace-comments)
}  // namespace penumbra::gears::HWY_NAMESPACE
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace penumbra::gears {

HWY_EXPORT(gather_kernel);
HWY_EXPORT(narrow_kernel);
HWY_EXPORT(drop_solid_back_faces_kernel);
HWY_EXPORT(keep_kernel);
HWY_EXPORT(setup_batch_kernel);
HWY_EXPORT(hidden_lanes_kernel);
HWY_EXPORT(raster_rows_kernel);
HWY_EXPORT(raster_rows_or_kernel);
HWY_EXPORT(raster_samples_kernel);

void CandidateBatch::reserve(size_t most) {
  // Called per pixel chunk by keep(): checking 23 vectors each time took 1.5–3 % in profiles.
  if (most <= reserved_) return;
  // Grown by half at least, into fresh buffers: the old contents need no copy, the new lanes no
  // zeroing (a dense model's first lists grew these 24 arrays many times, each time copied and
  // zero-filled, fresh pages faulted in).
  reserved_ = std::max(most, reserved_ + reserved_ / 2);
  for (auto* a : {&v[0], &v[1], &v[2], &v[3], &v[4], &v[5], &v[6], &v[7], &v[8], &zmin, &hx0,
                  &hx1,  &hy0,  &hy1,  &nx,   &ny,   &nz,   &nd,   &n1,   &lmin, &lmax})
    *a = UninitVector<float>(reserved_);
  for (auto* a : {&tri, &opaque, &solid}) *a = UninitVector<uint32_t>(reserved_);
}

void CandidateBatch::pad() {
  pad_setup();
  // Padding lanes are beyond every depth too (never kept by keep()).
  for (int i = count; i < padded; ++i) {
    zmin[i] = kInfinity;
    hx0[i] = hy0[i] = -kInfinity;
    hx1[i] = hy1[i] = kInfinity;
    nx[i] = ny[i] = nz[i] = nd[i] = n1[i] = 0.0f;
    lmin[i] = -kInfinity, lmax[i] = kInfinity;
    solid[i] = kNoSolid;
  }
}

void CandidateBatch::pad_setup() {
  // Padding lanes: a degenerate triangle at the origin (det = 0: always rejected). A pixel's
  // batch is only set up and rasterized: its cull arrays are not padded.
  padded = (count + kLanes - 1) / kLanes * kLanes;
  for (int i = count; i < padded; ++i) {
    tri[i] = 0;
    opaque[i] = 0;
    for (auto& a : v) a[i] = 0.0f;
  }
}

void CandidateBatch::gather(const PackedTriangle* tris, const TrianglePlane* planes,
                            const CellPair* begin, const CellPair* end, const ItemBounds& item) {
  // The list is sorted by zmin: the depth cut keeps a prefix.
  end = std::partition_point(
      begin, end, [&](const CellPair& pair) { return tris[pair.item].zmin <= item.zmax; });
  reserve(static_cast<size_t>(end - begin) + kLanes);
  read = static_cast<int>(end - begin);
  HWY_DYNAMIC_DISPATCH(gather_kernel)(*this, tris, planes, begin, end, item);
  pad();
}

void CandidateBatch::narrow(const CandidateBatch& from, const ItemBounds& group, const Vec3* points,
                            int point_count, uint64_t outside) {
  const int end = from.depth_prefix(group.zmax);
  reserve(static_cast<size_t>(end) + 2 * kLanes);
  HWY_DYNAMIC_DISPATCH(narrow_kernel)(*this, from, end, group, points, point_count, outside);
  read = end;
  pad();
}

void CandidateBatch::drop_solid_back_faces(const SampleBox& samples) {
  if (samples.outside == 0 || count == 0) return;
  HWY_DYNAMIC_DISPATCH(drop_solid_back_faces_kernel)(*this, samples);
  pad();
}

void CandidateBatch::keep(const CandidateBatch& from, int begin, int end, const ItemBounds& bounds,
                          const Vec3& p, const ShadowBoxCull* box, const uint32_t* rows,
                          uint64_t outside) {
  reserve(static_cast<size_t>(end - begin) + 2 * kLanes);
  HWY_DYNAMIC_DISPATCH(keep_kernel)(*this, from, begin, end, bounds, p, box, rows, outside);
  pad_setup();
}

uint32_t setup_batch(const CandidateBatch& batch, int first, const PixelLight& light, Vec2 uv_lo,
                     Vec2 uv_hi, int grid_k, LineBatch& out) {
  return HWY_DYNAMIC_DISPATCH(setup_batch_kernel)(batch, first, light, uv_lo, uv_hi, grid_k, out);
}

uint32_t hidden_lanes(const ShadowCells& cells, uint32_t lanes, const uint32_t* rows) {
  return HWY_DYNAMIC_DISPATCH(hidden_lanes_kernel)(cells, lanes, rows);
}

uint32_t raster_rows(const LineBatch& lines, int lane, int k, uint32_t* rows) {
  return HWY_DYNAMIC_DISPATCH(raster_rows_kernel)(lines, lane, k, rows);
}

uint32_t raster_rows_or(const LineBatch& lines, uint32_t lanes, int k, uint32_t* rows) {
  return HWY_DYNAMIC_DISPATCH(raster_rows_or_kernel)(lines, lanes, k, rows);
}

bool raster_samples(const LineBatch& lines, int lane, const float* u, const float* v, int n,
                    uint64_t* words) {
  return HWY_DYNAMIC_DISPATCH(raster_samples_kernel)(lines, lane, u, v, n, words);
}

void rows_to_words(const uint32_t* rows, int k, uint64_t* words) {
  if (64 % k == 0) {  // k = 1, 2, 4, 8, 16, 32: whole rows per word, assembled in a register
    const int per = 64 / k, count = (k * k + 63) / 64;
    for (int w = 0; w < count; ++w) {
      uint64_t x = 0;
      for (int r = 0; r < per && w * per + r < k; ++r) x |= uint64_t{rows[w * per + r]} << (r * k);
      words[w] |= x;
    }
    return;
  }
  for (int j = 0; j < k; ++j) {
    const uint64_t bits = rows[j];
    const int p = j * k;
    words[p >> 6] |= bits << (p & 63);
    if ((p & 63) + k > 64) words[(p >> 6) + 1] |= bits >> (64 - (p & 63));
  }
}

}  // namespace penumbra::gears
#endif  // HWY_ONCE
