// Inside the closed surfaces of ExactScene::solids: the winding number at a point, and balls the
// surface misses, which prove a receiver in umbra without projecting anything (exact_visibility).
#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "penumbra/shadows/exact/exact.hpp"

namespace penumbra {

/// Slab test of the segment origin + t·dir, t ∈ [0, 1], against a box (conservative: widened by a
/// relative 1e-9 so rounding never drops a touching box).
bool segment_meets_box(const DVec3& origin, const DVec3& dir, const Vec3& lo, const Vec3& hi);

/// +1 / −1 when origin + t·seg, t ∈ [0, 1], crosses the triangle (a, b, c) going against / along
/// its normal, 0 when it misses, kUnsure when it passes within a relative 1e-9 of its boundary or
/// plane.
inline constexpr int kUnsure = 2;
int signed_crossing(const DVec3& origin, const DVec3& seg, const DVec3& a, const DVec3& b,
                    const DVec3& c);

/// The winding number of solid `s` at p, counted along a ray from p out of its box. False when
/// unsure (the ray passes within a relative 1e-9 of an edge or runs nearly in a triangle's plane).
bool winding_number(const ExactScene& scene, uint32_t s, const DVec3& p, int& winding);

/// Up to kMaxInnerBalls balls (and no more than its triangles, at least 8) inside solid `s`, in
/// groups of kBallGroup neighbours (Morton order of their centres; see group_inner_balls): each
/// misses the solid's surface and caps (its radius is the distance from its centre to them, less a
/// relative 1e-6), and the winding number at its centre, hence over all of it, is non-zero.
/// Centres: the voxels of a grid over the solid's box that are farthest from its walls (the voxels
/// its triangles touch) and from the outside, none inside a larger kept ball. Deterministic (not
/// thread-dependent). `triangles`: the solid's occluders. The grid has 8·∛(triangle count) voxels
/// along the box's longest side, 8 to kInnerBallVoxels. At most four candidates per ball allowed
/// are measured (a nearest-point query and a winding ray each), and no more than `measure_budget`,
/// which is decreased by the count (a frame's budget, shared by its solids).
std::vector<ExactInnerBall> find_inner_balls(const ExactScene& scene, uint32_t s,
                                             std::span<const uint32_t> triangles,
                                             size_t& measure_budget);
/// The measurements a frame spends on inner balls, its solids taken largest first.
inline constexpr size_t kInnerBallBudget = 4096;
inline constexpr size_t kMaxInnerBalls = 128;
inline constexpr int kInnerBallVoxels = 48;
inline constexpr size_t kBallGroup = 8;

/// Orders `balls` by the Morton code of their centres in `box` (ties by the given order) and
/// returns their groups of kBallGroup consecutive ones, each with a ball holding all of them.
std::vector<ExactBallGroup> group_inner_balls(std::vector<ExactInnerBall>& balls,
                                              const Bounds3& box);

/// Is the receiver p in umbra by the solids' inner balls: does every segment from p to the light
/// parallelogram (corner, edge_u, edge_v; box `light_box`, projection `proj` from p) pass through
/// one of them, under the premises that make such a segment cross a solid's surface (see the
/// definition)? Exact up to a set of measure zero; false when it cannot be shown this way.
/// `solid_met` (one flag per solid; empty: all): the solids whose balls are tried — a solid whose
/// balls hide the light has triangles in the pyramid, so a traversal meets it.
bool inner_balls_hide_light(const ExactScene& scene, const DVec3& p, const DVec3& corner,
                            const DVec3& edge_u, const DVec3& edge_v, const Bounds3& light_box,
                            const LightProjection& proj, std::span<const uint8_t> solid_met = {});

}  // namespace penumbra
