// GEARS, beyond the paper: per-work-item culling of a cell's candidate triangles. A grid cell
// mixes samples at very different depths (bunny top and the ground behind it), so its list holds
// ~30× more triangles than block any one sample. Each work item (≤ 32 depth-sorted samples of one
// cell) keeps only the triangles whose penumbra can reach one of *its* samples, by four slab tests
// in the light's "edge-angle" coordinates, plus the depth cut.
//
// Why it is conservative. Light = [lx0, lx1] × [ly0, ly1] at z = 0; sample P (P.z > 0) is blocked
// by H ∈ T from light point X iff P = X + t·(H − X) with t = P.z / H.z ≥ 1. Then
//   P.x − lx0 = t·(H.x − lx0) + (1 − t)·(X.x − lx0) ≤ t·(H.x − lx0)   (1 − t ≤ 0, X.x ≥ lx0),
// so (P.x − lx0)/P.z ≤ (H.x − lx0)/H.z ≤ max over T's vertices (a linear-fractional function with a
// positive denominator is extremal at a vertex); symmetrically (P.x − lx1)/P.z ≥ min over the
// vertices of (v.x − lx1)/v.z, and the same in y. A triangle whose slab misses every sample's
// value blocks none of them. Triangles reaching z ≤ 0, and sphere lights (the light is not flat),
// are never culled this way.
#pragma once

#include <cstdint>
#include <vector>

#include "penumbra/core/uninit_vector.hpp"
#include "penumbra/shadows/gears/assign.hpp"
#include "penumbra/shadows/gears/grid_camera.hpp"

namespace penumbra::gears {

/// One occluder, packed into a cache line for the gather: vertices (light space, unmirrored: the
/// rasterizer's input) and its cull bounds (this pass's mirrored depth).
struct alignas(64) PackedTriangle {
  float v[9];       // ax ay az bx by bz cx cy cz
  float zmin;       // nearest depth from the light
  float hx0, hx1;   // max (v.x − lx0)/v.z, min (v.x − lx1)/v.z over the vertices
  float hy0, hy1;   // the same in y
  uint32_t opaque;  // TriangleSoup::opaque
  uint32_t solid;   // gears/solids.hpp: its solid, or kNoSolid
};

/// The samples of one work item, in the same coordinates: a triangle can block one of them only
/// if may_block() holds.
struct ItemBounds {
  float zmax;      // deepest sample, at least the light's deepest point
  float ix0, ix1;  // min (P.x − lx0)/P.z, max (P.x − lx1)/P.z over the samples
  float iy0, iy1;
};

/// The light's extent in light space, or none (sphere): culling then reduces to the depth cut.
struct FlatLight {
  bool flat = false;
  float lx0 = 0, lx1 = 0, ly0 = 0, ly1 = 0;
  // Deepest light point (0; r for a sphere). A blocker on the segment from sample P to light point
  // X lies no deeper than max(P.z, X.z): samples within a sphere's depth slab can be blocked by
  // triangles deeper than themselves, so the depth cut compares against max(P.z, max_z).
  float max_z = 0;
};
FlatLight flat_light(const GridCamera& camera);
/// Rays only go to the light samples: with shared sample positions (light uv = light-space xy for
/// a flat light) the bounds may use their box [lo, hi] instead of the whole light.
FlatLight shrink_to_samples(FlatLight light, Vec2 lo, Vec2 hi);

/// Packs the soup for one pass (`side` mirrors depths as in assign_triangles); `zmin` is that
/// pass's per-triangle nearest depth (CellTriangles::zmin).
UninitVector<PackedTriangle> pack_triangles(const TriangleSoup& soup, int side,
                                            const std::vector<float>& zmin, const FlatLight& light);

/// Bounds of samples (x[i], y[i], z[i]) (z: this pass's depth).
ItemBounds item_bounds(const FlatLight& light, const float* x, const float* y, const float* z,
                       int count);

/// An occluder's plane, for the per-pixel separating-plane cull: T can block sample P from light
/// point X only if the segment P–X meets T's plane, so not if P and every light point lie strictly
/// on one side of it. On closed meshes this drops the surface around a lit sample, which the slabs
/// keep (seen from P its neighbours span every edge angle). Unmirrored light space.
struct TrianglePlane {
  float nx, ny, nz, d;  // side of q: n·q − d
  float n1;             // |n|₁, scales the rounding tolerance
  float lmin, lmax;  // min and max of n·X − d over the light's corners, widened by the tolerance
  float pad;
};

/// Relative tolerance of the plane tests: float evaluation of n·P − d errs by ~10⁻⁷ of
/// |n|₁·|P|∞ + |d|, Embree's and the rasterizer's own segment tests by the same order; a sample
/// is only called strictly on one side beyond 10⁻⁵ of that.
inline constexpr float kPlaneRel = 1e-5f;

/// Planes of the soup's triangles against `light_corners` (unmirrored light space; for the light
/// samples' box of a flat light, its four corners at z = 0).
UninitVector<TrianglePlane> triangle_planes(const TriangleSoup& soup,
                                            const std::vector<Vec3>& light_corners);
/// The corners the plane test bounds the light points by: the flat light's (sample) box at z = 0,
/// or the camera's light corners (a sphere's cube, a point).
/// Splits the samples (x[i], y[i], z[i]), i < count, of one work item into groups of at most
/// `group_size` that lie close together in the slab coordinates ((x − lx0)/z, (y − ly0)/z): a k-d
/// split at the median of the wider coordinate. `order` receives a permutation of 0 … count − 1,
/// `ends` the end of each group in it. A light that is not flat, or a sample on the light plane,
/// gives one group in the given order (the slabs then cull nothing).
void group_samples(const FlatLight& light, const float* x, const float* y, const float* z,
                   int count, int group_size, std::vector<int>& order, std::vector<int>& ends);

std::vector<Vec3> plane_test_corners(const FlatLight& light, const GridCamera& camera);

/// Cull bounds (PackedTriangle's zmin, hx0 … hy1) of a light-space box [lo, hi] standing for every
/// triangle inside it, widened beyond the rounding of its triangles' own bounds (geometrically,
/// by 10⁻⁴ of its extent, and as pack_triangles widens): a sample for which may_block() fails on
/// the box fails it on each of those triangles. A box reaching the light plane culls nothing.
PackedTriangle box_cull_bounds(const FlatLight& light, Vec3 lo, Vec3 hi);

inline bool may_block(const PackedTriangle& t, const ItemBounds& b) {
  return (t.zmin <= b.zmax) & (b.ix0 <= t.hx0) & (b.ix1 >= t.hx1) & (b.iy0 <= t.hy0) &
         (b.iy1 >= t.hy1);
}

}  // namespace penumbra::gears
