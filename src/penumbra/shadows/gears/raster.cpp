#include "penumbra/shadows/gears/raster.hpp"

#include <algorithm>
#include <bit>
#include <cstddef>
#include <cstring>

#include "penumbra/shadows/gears/solids.hpp"
#include "penumbra/shadows/method.hpp"

#if defined(__AVX512F__)
#include <immintrin.h>
#endif

// The 64-byte vector helpers below are internal (and inlined); without AVX-512 in the target
// flags GCC warns that passing them by value would change an ABI nobody outside this file uses.
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic ignored "-Wpsabi"
#endif

namespace penumbra::gears {

namespace {

constexpr float kTieMargin = static_cast<float>(1.0 - kShadowSegmentEnd);

// GCC/Clang vector extensions: one register of 16 lanes (AVX-512 with -march=native, pairs or
// quads of narrower registers elsewhere), no intrinsics needed for the arithmetic.
typedef float vf __attribute__((vector_size(64)));
typedef int32_t vi __attribute__((vector_size(64)));
typedef uint32_t vu __attribute__((vector_size(64)));

inline vf load(const float* p) {
  vf r;
  std::memcpy(&r, p, sizeof(r));
  return r;
}
inline void store(float* p, vf v) {
  std::memcpy(p, &v, sizeof(v));
}
inline vf splat(float x) {
  return vf{} + x;
}
inline vf vmax(vf a, vf b) {
  return a > b ? a : b;
}
inline vf vmin(vf a, vf b) {
  return a < b ? a : b;
}

inline uint32_t movemask(vi m) {
#if defined(__AVX512F__)
  __m512i x;
  std::memcpy(&x, &m, sizeof(x));
  return _mm512_cmplt_epi32_mask(x, _mm512_setzero_si512());
#else
  uint32_t bits = 0;
  for (int l = 0; l < kLanes; ++l) bits |= static_cast<uint32_t>(m[l] != 0) << l;
  return bits;
#endif
}

/// Bit l of `bits` as lane l of a comparison-style vector (−1 or 0).
inline vi lane_mask(uint32_t bits) {
  const vi lane_index = {0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15};
  return ((vi{} + static_cast<int32_t>(bits)) >> lane_index & 1) != 0;
}

/// floor(y) for y ≥ −40 (after clamping), as exact integers in a float-free vector.
inline vi floor_small(vf y) {
  return __builtin_convertvector(y + 64.0f, vi) - 64;
}

/// The vertices of batch lanes [first, first + 16) relative to the pixel point p: ax ay az bx … cz.
inline void relative_vertices(const CandidateBatch& batch, int first, vf px, vf py, vf pz,
                              vf r[9]) {
  for (int c = 0; c < 9; ++c)
    r[c] = load(&batch.v[c][first]) - (c % 3 == 0 ? px : c % 3 == 1 ? py : pz);
}

/// Separating-axis completion of the setup for the common case, 16 lanes: all three vertices
/// (a, b, c, relative to the pixel point p) between the light plane and p (−p.z < a.z < 0). The
/// triangle's shadow on the light is then the triangle of its vertices' projections from p, so
/// its uv bounds must overlap the sample box [uv_lo, uv_hi] — and, with grid_k > 0, hold a sample
/// centre. False only where that fails; lanes not between pass. Shared by setup_batch and the
/// per-pixel cull (CandidateBatch::keep), which must compute bit-identical decisions.
inline vi shadow_box_holds_samples(const vf r[9], vf px, vf py, vf pzv, Vec2 uv_lo, Vec2 uv_hi,
                                   int grid_k, ShadowCells* cells = nullptr) {
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
    const vi top = vi{} + (grid_k - 1), zero = vi{} + 0;
    const vi ci0 = i0 > zero ? i0 : zero, ci1 = i1 < top ? i1 : top;
    const vi cj0 = j0 > zero ? j0 : zero, cj1 = j1 < top ? j1 : top;
    overlap &= (ci0 <= ci1) & (cj0 <= cj1);
    if (cells != nullptr) {
      std::memcpy(cells->box[0], &ci0, sizeof(ci0));
      std::memcpy(cells->box[1], &ci1, sizeof(ci1));
      std::memcpy(cells->box[2], &cj0, sizeof(cj0));
      std::memcpy(cells->box[3], &cj1, sizeof(cj1));
      cells->boxed = movemask(between & overlap);
    }
  }
  return overlap | ~between;
}

/// The lanes whose triangle's solid (kNoSolid: none) is one of `outside`'s bits.
inline vi solid_lanes(const uint32_t* solid, uint64_t outside) {
  vi s;
  std::memcpy(&s, solid, sizeof(s));
  const vi low = vi{} + static_cast<int32_t>(static_cast<uint32_t>(outside));
  const vi high = vi{} + static_cast<int32_t>(static_cast<uint32_t>(outside >> 32));
  const vi word = s < 32 ? low : s < kMaxSolids ? high : vi{};
  return ((word >> (s & 31)) & 1) != 0;
}

}  // namespace

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

#if defined(__AVX512F__)
// GCC 12 flags the intrinsics' own _mm512_undefined pass-through operands as maybe uninitialized.
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#endif
namespace {

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

}  // namespace
#endif

void CandidateBatch::gather(const PackedTriangle* tris, const TrianglePlane* planes,
                            const CellPair* begin, const CellPair* end, const ItemBounds& item) {
  // The list is sorted by zmin: the depth cut keeps a prefix.
  end = std::partition_point(
      begin, end, [&](const CellPair& pair) { return tris[pair.item].zmin <= item.zmax; });
  reserve(static_cast<size_t>(end - begin) + kLanes);
  count = 0;
  read = static_cast<int>(end - begin);
  // The list is in depth order, its triangles scattered through `tris`: the loads miss the cache
  // and the loop's few instructions cannot hide that, so the lines are prefetched well ahead.
  constexpr std::ptrdiff_t kAhead = 16;
  const CellPair* pair = begin;
#if defined(__AVX512F__)
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
    auto put = [&](auto* to, __m512i x) {
      _mm512_storeu_si512(to + count, _mm512_maskz_compress_epi32(m, x));
    };
    for (int c = 0; c < 9; ++c) put(v[c].data(), row[c]);
    put(zmin.data(), row[9]);
    put(hx0.data(), row[10]);
    put(hx1.data(), row[11]);
    put(hy0.data(), row[12]);
    put(hy1.data(), row[13]);
    put(opaque.data(), row[14]);
    put(solid.data(), row[15]);
    put(tri.data(), _mm512_load_si512(id));
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
    tri[i] = t;
    for (int c = 0; c < 9; ++c) v[c][i] = p.v[c];
    zmin[i] = p.zmin, hx0[i] = p.hx0, hx1[i] = p.hx1, hy0[i] = p.hy0, hy1[i] = p.hy1;
    opaque[i] = p.opaque;
    solid[i] = p.solid;
    count += may_block(p, item);
  }
  // Planes only for the kept ones (a second cache line per triangle, read once per item).
  for (int i = 0; i < count; ++i) {
    if (i + kAhead < count) __builtin_prefetch(&planes[tri[i + kAhead]]);
    const TrianglePlane& q = planes[tri[i]];
    nx[i] = q.nx, ny[i] = q.ny, nz[i] = q.nz, nd[i] = q.d, n1[i] = q.n1;
    lmin[i] = q.lmin, lmax[i] = q.lmax;
  }
  pad();
}
#if defined(__AVX512F__) && defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic pop
#endif

namespace {

/// Lanes `m` of src[first, first + 16) to to[at...], in order (4-byte elements: floats, ids,
/// flags).
template <class T>
inline void compress_lanes(T* to, int at, const T* src, int first, uint32_t m) {
#if defined(__AVX512F__)
  // Compress in a register, then one full store (the buffers have 2 × 16 spare lanes; later lanes
  // overwrite the tail): the masked compress-store to memory is several times slower.
  _mm512_storeu_si512(to + at, _mm512_maskz_compress_epi32(static_cast<__mmask16>(m),
                                                           _mm512_loadu_si512(src + first)));
#else
  for (uint32_t l = m; l; l &= l - 1) to[at++] = src[first + std::countr_zero(l)];
#endif
}

}  // namespace

void CandidateBatch::narrow(const CandidateBatch& from, const ItemBounds& group, const Vec3* points,
                            int point_count, uint64_t outside) {
  const int end = from.depth_prefix(group.zmax);
  reserve(static_cast<size_t>(end) + 2 * kLanes);
  count = 0;
  const vi lane_index = {0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15};
  for (int first = 0; first < end; first += kLanes) {
    vi kept = (lane_index + first < end) & (splat(group.ix0) <= load(&from.hx0[first])) &
              (splat(group.ix1) >= load(&from.hx1[first])) &
              (splat(group.iy0) <= load(&from.hy0[first])) &
              (splat(group.iy1) >= load(&from.hy1[first]));
    if (point_count > 0 && movemask(kept) != 0) {
      const vf nxv = load(&from.nx[first]), nyv = load(&from.ny[first]),
               nzv = load(&from.nz[first]), d = load(&from.nd[first]);
      const vf n1 = load(&from.n1[first]), abs_d = vmax(d, -d);
      vi all_above = kept, all_below = kept;
      for (int i = 0; i < point_count; ++i) {
        const Vec3& q = points[i];
        const float q_inf = std::max({std::abs(q.x), std::abs(q.y), std::abs(q.z)});
        const vf side = nxv * q.x + nyv * q.y + nzv * q.z - d;
        const vf tol = (2.0f * kPlaneRel) * (n1 * q_inf + abs_d);
        all_above &= side > tol;
        all_below &= side < -tol;
      }
      kept &= ~((all_above & (load(&from.lmin[first]) > 0.0f)) |
                (all_below &
                 ((load(&from.lmax[first]) < 0.0f) | solid_lanes(&from.solid[first], outside))));
    }
    append_lanes(from, first, movemask(kept));
  }
  read = end;
  pad();
}

void CandidateBatch::append_lanes(const CandidateBatch& from, int first, uint32_t m) {
  if (m == 0) return;
  for (int c = 0; c < 9; ++c) compress_lanes(v[c].data(), count, from.v[c].data(), first, m);
  for (auto [to, src] : {std::pair{&zmin, &from.zmin},
                         {&hx0, &from.hx0},
                         {&hx1, &from.hx1},
                         {&hy0, &from.hy0},
                         {&hy1, &from.hy1},
                         {&nx, &from.nx},
                         {&ny, &from.ny},
                         {&nz, &from.nz},
                         {&nd, &from.nd},
                         {&n1, &from.n1},
                         {&lmin, &from.lmin},
                         {&lmax, &from.lmax}})
    compress_lanes(to->data(), count, src->data(), first, m);
  compress_lanes(tri.data(), count, from.tri.data(), first, m);
  compress_lanes(opaque.data(), count, from.opaque.data(), first, m);
  compress_lanes(solid.data(), count, from.solid.data(), first, m);
  count += std::popcount(m);
}

void CandidateBatch::drop_solid_back_faces(const SampleBox& samples) {
  if (samples.outside == 0 || count == 0) return;
  float box_inf = 0.0f;
  for (int a = 0; a < 3; ++a)
    box_inf = std::max({box_inf, std::abs(samples.lo[a]), std::abs(samples.hi[a])});
  const vi lane_index = {0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15};
  const int end = count;
  count = 0;  // compacted in place: lanes are read before the stores that reach them
  for (int first = 0; first < end; first += kLanes) {
    // The most positive side over the box: every sample strictly behind this face of a solid
    // they all lie outside of (keep()'s test, at twice its tolerance for the whole box).
    const vf nxv = load(&nx[first]), nyv = load(&ny[first]), nzv = load(&nz[first]);
    const vf d = load(&nd[first]);
    const vf most = vmax(nxv * samples.lo.x, nxv * samples.hi.x) +
                    vmax(nyv * samples.lo.y, nyv * samples.hi.y) +
                    vmax(nzv * samples.lo.z, nzv * samples.hi.z) - d;
    const vf tol = (2.0f * kPlaneRel) * (load(&n1[first]) * box_inf + vmax(d, -d));
    const vi behind = (most < -tol) & solid_lanes(&solid[first], samples.outside);
    append_lanes(*this, first, movemask((lane_index + first < end) & ~behind));
  }
  pad();
}

void CandidateBatch::keep(const CandidateBatch& from, int begin, int end, const ItemBounds& bounds,
                          const Vec3& p, const ShadowBoxCull* box, const uint32_t* rows,
                          uint64_t outside) {
  ShadowCells cells;
  ShadowCells* want_cells = rows != nullptr && box != nullptr && box->grid_k > 0 ? &cells : nullptr;
  reserve(static_cast<size_t>(end - begin) + 2 * kLanes);
  count = 0;
  const vi lane_index = {0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15};
  const vf px = splat(p.x), py = splat(p.y), pz = splat(p.z);
  const vf p_inf = splat(std::max({std::abs(p.x), std::abs(p.y), std::abs(p.z)}));
  for (int first = begin; first < end; first += kLanes) {
    // may_block() on 16 lanes (padding lanes fail the depth cut), within [begin, end).
    vi kept = (lane_index + first < end) & (load(&from.zmin[first]) <= splat(bounds.zmax)) &
              (splat(bounds.ix0) <= load(&from.hx0[first])) &
              (splat(bounds.ix1) >= load(&from.hx1[first])) &
              (splat(bounds.iy0) <= load(&from.hy0[first])) &
              (splat(bounds.iy1) >= load(&from.hy1[first]));
    // Separating plane: P and every light corner strictly on one side of T's plane.
    const vf d = load(&from.nd[first]);
    const vf side =
        load(&from.nx[first]) * px + load(&from.ny[first]) * py + load(&from.nz[first]) * pz - d;
    const vf tol = kPlaneRel * (load(&from.n1[first]) * p_inf + vmax(d, -d));
    // And a face of a solid the sample lies outside of, seen strictly from behind.
    kept &= ~(((side > tol) & (load(&from.lmin[first]) > 0.0f)) |
              ((side < -tol) &
               ((load(&from.lmax[first]) < 0.0f) | solid_lanes(&from.solid[first], outside))));
    if (box != nullptr && movemask(kept) != 0) {
      // setup_batch's shadow-box test, moved ahead of it with the same arithmetic: it rejects the
      // same triangles, only before their edge planes are built (dense meshes: most of them).
      vf r[9];
      relative_vertices(from, first, px, py, pz, r);
      kept &=
          shadow_box_holds_samples(r, px, py, pz, box->uv_lo, box->uv_hi, box->grid_k, want_cells);
      if (want_cells != nullptr) kept &= ~lane_mask(hidden_lanes(cells, movemask(kept), rows));
    }
    const uint32_t m = movemask(kept);
    if (m == 0) continue;
    for (int c = 0; c < 9; ++c) compress_lanes(v[c].data(), count, from.v[c].data(), first, m);
    compress_lanes(tri.data(), count, from.tri.data(), first, m);
    compress_lanes(opaque.data(), count, from.opaque.data(), first, m);
    count += std::popcount(m);
  }
  pad_setup();
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

uint32_t setup_batch(const CandidateBatch& batch, int first, const PixelLight& light, Vec2 uv_lo,
                     Vec2 uv_hi, int grid_k, LineBatch& out) {
  const vf px = splat(light.p.x), py = splat(light.p.y), pz = splat(light.p.z);
  // Vertices relative to the pixel point.
  vf r[9];
  relative_vertices(batch, first, px, py, pz, r);
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
    store(out.a[m], A[m]);
    store(out.b[m], B[m]);
    store(out.c[m], C[m]);
  }
  out.cells.boxed = 0;
  if (light.axis_aligned)
    ok &= shadow_box_holds_samples(r, px, py, pz, uv_lo, uv_hi, grid_k, &out.cells);
  const int live = std::min(kLanes, batch.count - first);
  const uint32_t result = movemask(ok) & ((live >= 32 ? ~0u : (1u << live) - 1u));
  if (grid_k > 0 && result != 0) {
    // Row-span form: index space of sample (i, j) at ((i + ½)/k, (j + ½)/k).
    const float kf = static_cast<float>(grid_k);
    for (int m = 0; m < 4; ++m) {
      store(out.al[m], kf * A[m] + 0.5f * (B[m] + C[m]));
      store(out.inv[m], B[m] != 0.0f ? -1.0f / B[m] : splat(0.0f));
      store(out.lo_off[m], B[m] > 0.0f ? splat(0.0f) : splat(-kInfinity));
      store(out.hi_off[m], B[m] < 0.0f ? splat(0.0f) : splat(kInfinity));
    }
  }
  return result;
}

namespace {

/// Covered columns lo … hi of 16 (triangle, row) pairs, element by element: lane l is row j[l] of
/// the triangle whose row-span lines are lane l of al, c, inv, lo_off, hi_off (b: the lines'
/// u slopes, for lines parallel to the rows); `valid` marks non-empty spans. Branch-free over
/// the four lines (their slopes' signs are unpredictable): line m bounds i from below by t
/// (b > 0) or from above (b < 0); the offsets pick which (gears/raster.hpp). Shared by the
/// per-triangle form (16 rows of one triangle) and the per-row form (one row of 16 triangles), so
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
  out.lo = lo0 > 0 ? lo0 : vi{} + 0;
  out.hi = hi0 < (k - 1) ? hi0 : vi{} + (k - 1);
  out.valid = (out.lo <= out.hi) & ~empty;
  return out;
}

/// Bits lo … hi of each valid span (hi ≤ 31: 2 << 31 wraps to 0, the full row).
inline vu span_bits(const RowSpans& s) {
  vu mask = (vu{} + 2u) << __builtin_convertvector(s.hi > 0 ? s.hi : vi{} + 0, vu);
  mask -= (vu{} + 1u) << __builtin_convertvector(s.lo < 31 ? s.lo : vi{} + 31, vu);
  return mask & __builtin_convertvector(s.valid, vu);
}

/// Rows jb .. jb+15 of triangle `lane`'s coverage (row j: bits lo..hi); `valid` gets the non-empty
/// rows.
inline vu span_rows(const LineBatch& lines, int lane, int k, int jb, uint32_t& valid_rows) {
  const vf lane_index = {0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15};
  vf al[4], c[4], inv[4], lo_off[4], hi_off[4], b[4];
  for (int m = 0; m < 4; ++m) {
    al[m] = splat(lines.al[m][lane]), c[m] = splat(lines.c[m][lane]);
    inv[m] = splat(lines.inv[m][lane]), b[m] = splat(lines.b[m][lane]);
    lo_off[m] = splat(lines.lo_off[m][lane]), hi_off[m] = splat(lines.hi_off[m][lane]);
  }
  // A line parallel to the rows (b = 0) is rare: kept out of the hot path.
  const bool flat = (lines.b[0][lane] == 0.0f) | (lines.b[1][lane] == 0.0f) |
                    (lines.b[2][lane] == 0.0f) | (lines.b[3][lane] == 0.0f);
  const vf j = lane_index + static_cast<float>(jb);
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
  vi j0, j1;
  std::memcpy(&j0, cells.box[2], sizeof(j0));
  std::memcpy(&j1, cells.box[3], sizeof(j1));
  const vi height = j1 - j0 + 1;
  const uint32_t few = movemask(height <= kShortRows) & cells.boxed & lanes;
  int tallest = 0;
  for (uint32_t l = few; l; l &= l - 1) tallest = std::max(tallest, height[std::countr_zero(l)]);
  // Fixed thresholds of 3, 5, 6 and 8 lanes measured alike on the dense models (k = 16).
  return std::popcount(few) * ((k + kLanes - 1) / kLanes) > tallest ? few : 0;
}

/// raster_rows_or for lanes whose shadow box is at most kShortRows rows tall (dense meshes: most
/// shadows hold one or two sample centres): one row of all 16 triangles at a time, only the rows
/// of their boxes (every covered sample lies in the box), instead of all k rows of each triangle.
uint32_t raster_short_or(const LineBatch& lines, uint32_t lanes, int k, uint32_t* rows) {
  vf al[4], c[4], inv[4], lo_off[4], hi_off[4], b[4];
  bool flat = false;
  for (int m = 0; m < 4; ++m) {
    al[m] = load(lines.al[m]), c[m] = load(lines.c[m]), inv[m] = load(lines.inv[m]);
    lo_off[m] = load(lines.lo_off[m]), hi_off[m] = load(lines.hi_off[m]), b[m] = load(lines.b[m]);
    flat |= (movemask(b[m] == 0.0f) & lanes) != 0;
  }
  vi j0, j1;
  std::memcpy(&j0, lines.cells.box[2], sizeof(j0));
  std::memcpy(&j1, lines.cells.box[3], sizeof(j1));
  uint32_t hit = 0;
  for (int dj = 0; dj < kShortRows; ++dj) {
    const vi j = j0 + dj;
    const uint32_t live = movemask(j <= j1) & lanes;
    if (live == 0) break;
    const vf jf = __builtin_convertvector(j, vf);
    const RowSpans s = flat ? row_spans<true>(al, c, inv, lo_off, hi_off, b, jf, k)
                            : row_spans<false>(al, c, inv, lo_off, hi_off, b, jf, k);
    const uint32_t covered = movemask(s.valid) & live;
    hit |= covered;
    alignas(64) uint32_t bits[kLanes];
    alignas(64) int32_t row[kLanes];
    const vu m = span_bits(s);
    std::memcpy(bits, &m, sizeof(bits));
    std::memcpy(row, &j, sizeof(row));
    for (uint32_t l = covered; l; l &= l - 1) {
      const int lane = std::countr_zero(l);
      rows[row[lane]] |= bits[lane];
    }
  }
  return hit;
}

}  // namespace

uint32_t hidden_lanes(const ShadowCells& cells, uint32_t lanes, const uint32_t* rows) {
  lanes &= cells.boxed;
  if (lanes == 0) return 0;
  vi i0, i1, j0, j1;
  std::memcpy(&i0, cells.box[0], sizeof(i0));
  std::memcpy(&i1, cells.box[1], sizeof(i1));
  std::memcpy(&j0, cells.box[2], sizeof(j0));
  std::memcpy(&j1, cells.box[3], sizeof(j1));
  // Bits i0 … i1 of a row (i1 ≤ 31: 2 << 31 wraps to 0, as in span_rows).
  const vu need = ((vu{} + 2u) << __builtin_convertvector(i1, vu)) -
                  ((vu{} + 1u) << __builtin_convertvector(i0, vu));
  // Shadows of dense meshes span a row or two: rows j0, j0 + 1 and j1 cover boxes of up to three
  // rows, read 16 lanes at once; taller boxes are never called hidden (they are rasterized).
  const vi j_mid = j0 + 1 < j1 ? j0 + 1 : j1;
  // Rows by a two-register permute (k ≤ 32 rows: callers' arrays hold 32): gathers are several
  // times slower on this hardware and took a quarter of keep()'s time.
#if defined(__AVX512F__)
  __m512i rows_lo, rows_hi;
  std::memcpy(&rows_lo, rows, sizeof(rows_lo));
  std::memcpy(&rows_hi, rows + kLanes, sizeof(rows_hi));
#endif
  auto row_of = [&](vi j) {
    vu r;
#if defined(__AVX512F__)
    __m512i idx;
    std::memcpy(&idx, &j, sizeof(idx));
    const __m512i g = _mm512_permutex2var_epi32(rows_lo, idx, rows_hi);
    std::memcpy(&r, &g, sizeof(r));
#else
    r = vu{};
    for (uint32_t l = lanes; l; l &= l - 1) r[std::countr_zero(l)] = rows[j[std::countr_zero(l)]];
#endif
    return r;
  };
  const vu blocked = row_of(j0) & row_of(j_mid) & row_of(j1);
  const vi hidden = ((blocked & need) == need) & (j1 - j0 <= 2);
  return movemask(hidden) & lanes;
}

uint32_t raster_rows(const LineBatch& lines, int lane, int k, uint32_t* rows) {
  uint32_t any = 0;
  for (int jb = 0; jb < k; jb += kLanes) {
    uint32_t valid;
    const vu mask = span_rows(lines, lane, k, jb, valid);
    // Rows j ≥ k are empty, so whole registers can be stored.
    std::memcpy(rows + jb, &mask, sizeof(mask));
    any |= valid << jb;
  }
  return any;
}

uint32_t raster_rows_or(const LineBatch& lines, uint32_t lanes, int k, uint32_t* rows) {
  const uint32_t few = short_lanes(lines.cells, lanes, k);
  uint32_t hit = few != 0 ? raster_short_or(lines, few, k, rows) : 0;
  lanes &= ~few;
  if (lanes == 0) return hit;
  for (int jb = 0; jb < k; jb += kLanes) {
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

bool raster_samples(const LineBatch& lines, int lane, const float* u, const float* v, int n,
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
