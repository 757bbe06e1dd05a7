// The projected silhouette of a large closed mesh from its edges. Seen from a receiver p outside
// a solid (ExactSolid) whose back faces may be culled, the kept faces' winding field on the light
// changes only across their silhouette edges (an edge whose two faces p sees from opposite sides,
// or a boundary edge of a kept face) and across the pyramid's faces. Inside the light's uv square
// the field is therefore fixed by the silhouette edges clipped to the pyramid plus its value along
// the square's left side, u = 0 — one ray from p to a point of that side counts the kept faces
// there, and the clipped edges' ends on the side step it. The area sweep (union_area.hpp) reads
// nothing else: the faces between silhouette edges are never visited. A hierarchy over the edges
// with normal cones over both faces skips every subtree that p sees from one side only.
#pragma once

#include <cmath>
#include <cstdint>
#include <span>
#include <vector>

#include "penumbra/shadows/exact/exact.hpp"
#include "penumbra/shadows/exact/union_area.hpp"

namespace penumbra {

/// Would every triangle of the cone's subtree (BVH node `node`) be culled for receiver p: seen
/// strictly from behind (keep_positive: normal · (p − x) < 0 for every normal of the cone and point
/// of its sphere), or strictly from the front? With φ the angle the sphere subtends from p, the
/// angle between a normal and p − x differs from the one between the axis and p − centre by at
/// most θ + φ. The stored (cos θ, sin θ) = R·(cos θ', sin θ') with θ' ≥ θ and R ≥ 1 (rounded
/// outward), so the sums below bound the true ones from the safe side; the margin of 1e-6 in the
/// cosine covers the axis' float length (within 2e-7 of 1) and is far above the rounding of the
/// per-triangle side tests.
inline bool subtree_culled(const ExactNodeCone& cone, const ExactBvh::Node& node, const DVec3& p,
                           bool keep_positive) {
  const DVec3 center = 0.5 * (DVec3(node.lo) + DVec3(node.hi));
  const DVec3 d = p - center;
  const DVec3 axis(cone.axis);
  // The axis on the kept side of p − centre: cos_axis has the kept sign, sin(θ + φ) ≥ 0 below,
  // so the test fails; decided before the square roots (most subtrees p sees from the front).
  const double along = glm::dot(axis, d);
  if (keep_positive ? along >= 0.0 : along <= 0.0) return false;
  const double dist = glm::length(d);
  const double radius = cone.radius;
  if (!(dist > radius)) return false;
  const double sin_phi = radius / dist, cos_phi = std::sqrt(1.0 - sin_phi * sin_phi);
  const double cos_theta = cone.cos_theta, sin_theta = cone.sin_theta;
  if (!(cos_theta * cos_phi - sin_theta * sin_phi > 0.0)) return false;  // θ + φ ≥ 90°
  const double sin_sum = sin_theta * cos_phi + cos_theta * sin_phi;      // sin(θ + φ)
  const double cos_axis = along / dist;
  return keep_positive ? cos_axis < -sin_sum - 1e-6 : cos_axis > sin_sum + 1e-6;
}

/// The cone of the unit normals `normals` (their sum's direction, the widest angle from it) in
/// `cone`'s axis, cos_theta, sin_theta, rounded outward to float, and the radius of `node`'s box's
/// bounding sphere; false (cone untouched) when they do not fit in one under 90°.
bool fit_normal_cone(std::span<const DVec3> normals, const ExactBvh::Node& node,
                     ExactNodeCone& cone);

/// The edge tree of solid `s` over its `triangles` (occluder indices): each edge once, shared
/// ones from the triangle of lower index, in a binned-SAH BVH of `leaf_size`.
ExactEdgeTree build_edge_tree(const std::vector<ExactOccluder>& occluders,
                              std::span<const uint32_t> triangles, uint32_t s, int leaf_size);

/// One receiver's query of one solid's edge tree.
struct EdgeSilhouetteQuery {
  const ExactScene* scene = nullptr;
  uint32_t solid = 0;
  DVec3 p{0.0};
  const LightProjection* proj = nullptr;
  DVec3 corner{0.0}, edge_v{0.0};  // the light's u = 0 side: corner + v·edge_v
  bool keep_positive = true;       // the faces p sees from their positive side are kept
  bool det_positive = true;        // det of the projection's rows (orientation in uv)
  uint32_t label = 0;              // the label of every edge appended (the divided sweep's group)
};

/// Appends to `uv` (and `label` to `labels`) the solid's kept faces' silhouette clipped to the
/// pyramid and, along u = 0, as many copies of each piece of the left side as kept faces lie over
/// it: inside the square the same winding field as the kept faces themselves. False, with
/// nothing appended, where that is not certain: a silhouette edge ending on the pyramid's near or
/// far face (a surface crossing the light's plane or passing next to p), one running along the left
/// side, or the counting ray passing within a relative 1e-9 of an edge. The caller then visits the
/// faces. `searched` grows by the edges tested.
bool append_edge_silhouette(const EdgeSilhouetteQuery& q, std::vector<UvEdge>& uv,
                            std::vector<uint32_t>& labels, uint64_t& searched);

}  // namespace penumbra
