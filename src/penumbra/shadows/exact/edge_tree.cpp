// The projected silhouette of a large closed mesh from a hierarchy over its edges (edge_tree.hpp).
#include "penumbra/shadows/exact/edge_tree.hpp"

#include <algorithm>
#include <cmath>

#include "penumbra/shadows/exact/solid_interior.hpp"

namespace penumbra {

bool fit_normal_cone(std::span<const DVec3> normals, const ExactBvh::Node& node,
                     ExactNodeCone& cone) {
  DVec3 sum(0.0);
  for (const DVec3& n : normals) sum += n;
  const double len = glm::length(sum);
  if (!(len > 1e-12)) return false;
  // The axis as stored (float), and θ measured from it: the bound holds for the stored cone.
  const Vec3 axis(sum / len);
  const DVec3 unit_axis = glm::normalize(DVec3(axis));
  double cos_theta = 1.0;
  for (const DVec3& n : normals) cos_theta = std::min(cos_theta, glm::dot(unit_axis, n));
  // A little wider than measured, against the rounding of the normals and dot products; then
  // rounded outward to float (cos down, sin and the radius up).
  cos_theta -= 1e-9;
  if (!(cos_theta > 0.0)) return false;
  const auto down = [](double x) {
    const float f = static_cast<float>(x);
    return static_cast<double>(f) <= x ? f : std::nextafter(f, -1.0f);
  };
  const auto up = [](double x) {
    const float f = static_cast<float>(x);
    return static_cast<double>(f) >= x ? f : std::nextafter(f, 2.0f * f + 1.0f);
  };
  cone.axis = axis;
  cone.cos_theta = down(cos_theta);
  cone.sin_theta = up(std::sqrt(std::max(0.0, 1.0 - cos_theta * cos_theta)));
  cone.radius = up(0.5 * glm::length(DVec3(node.hi) - DVec3(node.lo)) * (1.0 + 1e-9));
  return true;
}

namespace {

/// Fills the cones of the subtree at `index` (edges already in leaf order, so a subtree owns a
/// contiguous range) and returns that range.
std::pair<uint32_t, uint32_t> make_edge_cones(ExactEdgeTree& tree,
                                              const std::vector<DVec3>& unit_normals,
                                              const std::vector<ExactOccluder>& occluders,
                                              uint32_t s, uint32_t index,
                                              std::vector<DVec3>& scratch) {
  const ExactBvh::Node& node = tree.bvh.nodes()[index];
  std::pair<uint32_t, uint32_t> range{node.first, node.first + node.count};
  if (node.count == 0) {
    const auto left = make_edge_cones(tree, unit_normals, occluders, s, index + 1, scratch);
    const auto right = make_edge_cones(tree, unit_normals, occluders, s, node.first, scratch);
    range = {std::min(left.first, right.first), std::max(left.second, right.second)};
  }
  ExactNodeCone& cone = tree.cones[index];
  cone.triangles = range.second - range.first;  // edges, here
  scratch.clear();
  for (uint32_t e = range.first; e < range.second; ++e) {
    const ExactEdge& edge = tree.edges[e];
    if (edge.right == ExactOccluder::kNoNeighbour) return range;  // emitted whenever kept
    scratch.push_back(unit_normals[edge.left]);
    scratch.push_back(unit_normals[edge.right]);
  }
  if (fit_normal_cone(scratch, node, cone)) cone.solid = s;
  (void)occluders;
  return range;
}

}  // namespace

ExactEdgeTree build_edge_tree(const std::vector<ExactOccluder>& occluders,
                              std::span<const uint32_t> triangles, uint32_t s, int leaf_size) {
  ExactEdgeTree tree;
  std::vector<Bounds3> boxes;
  for (const uint32_t t : triangles) {
    const ExactOccluder& o = occluders[t];
    for (int k = 0; k < 3; ++k) {
      const uint32_t nb = o.neighbour[k];
      if (nb != ExactOccluder::kNoNeighbour && nb < t) continue;  // from the other side
      ExactEdge edge{o.v[k], o.v[k == 2 ? 0 : k + 1], t, nb};
      Bounds3 box;
      box.extend(Vec3(edge.a));
      box.extend(Vec3(edge.b));
      boxes.push_back(box);
      tree.edges.push_back(edge);
    }
  }
  if (tree.edges.empty()) return tree;
  tree.bvh.build(boxes, leaf_size);
  std::vector<ExactEdge> sorted(tree.edges.size());
  const std::vector<uint32_t>& order = tree.bvh.primitives();
  for (size_t k = 0; k < order.size(); ++k) sorted[k] = tree.edges[order[k]];
  tree.edges.swap(sorted);
  tree.bvh.renumber_in_leaf_order();
  std::vector<DVec3> unit_normals(occluders.size());
  for (const uint32_t t : triangles) unit_normals[t] = glm::normalize(occluders[t].normal);
  tree.cones.resize(tree.bvh.nodes().size());
  std::vector<DVec3> scratch;
  make_edge_cones(tree, unit_normals, occluders, s, 0, scratch);
  // The faces by first use in leaf order; the edges then name them there.
  std::vector<uint32_t> face_of(occluders.size(), ExactOccluder::kNoNeighbour);
  const auto face = [&](uint32_t t) {
    if (face_of[t] == ExactOccluder::kNoNeighbour) {
      face_of[t] = static_cast<uint32_t>(tree.faces.size());
      tree.faces.push_back({occluders[t].normal, occluders[t].v[0]});
    }
    return face_of[t];
  };
  for (ExactEdge& edge : tree.edges) {
    edge.left = face(edge.left);
    if (edge.right != ExactOccluder::kNoNeighbour) edge.right = face(edge.right);
  }
  return tree;
}

namespace {

/// A silhouette edge's end on the square's left side: moving up past it, the number of kept
/// faces over the points just right of u = 0 steps by `step`.
struct SideEvent {
  double y;
  int step;
};

/// Clips the light-uv image of segment from → to (world) to the pyramid and appends it; records
/// its ends on the left side. False when unsure (see append_edge_silhouette).
bool append_clipped(const LightProjection& proj, const DVec3& from, const DVec3& to,
                    std::vector<UvEdge>& uv, std::vector<SideEvent>& side) {
  const DVec3 ha = proj.homogeneous(from), hb = proj.homogeneous(to);
  double t0 = 0.0, t1 = 1.0;
  int plane0 = -1, plane1 = -1;  // the plane each end was clipped at
  for (int plane = 0; plane < 6; ++plane) {
    const double fa = clip_value(plane, ha), fb = clip_value(plane, hb);
    if (fa < 0.0 && fb < 0.0) return true;  // wholly outside: nothing in the pyramid
    if (fa < 0.0) {
      const double t = fa / (fa - fb);
      if (t > t0) t0 = t, plane0 = plane;
    } else if (fb < 0.0) {
      const double t = fa / (fa - fb);
      if (t < t1) t1 = t, plane1 = plane;
    }
  }
  if (!(t0 < t1)) return true;
  // Planes 0 and 1 are W ≥ kMinW and W ≤ kShadowSegmentEnd: the surface crosses a cap.
  if (plane0 == 0 || plane0 == 1 || plane1 == 0 || plane1 == 1) return false;
  const auto end_uv = [&](double t, int plane, const DVec3& h_end) {
    const DVec3 h = plane < 0 ? h_end : ha + t * (hb - ha);
    DVec2 q(h.x / h.z * kUvScale, h.y / h.z * kUvScale);
    // Ends on a side of the square lie on it exactly (the sweep folds u ≤ 0 onto the left side).
    if (plane == 2 || (plane < 0 && h.x == 0.0)) q.x = 0.0;
    if (plane == 3) q.x = kUvScale;
    if (plane == 4) q.y = 0.0;
    if (plane == 5) q.y = kUvScale;
    return q;
  };
  const DVec2 qa = end_uv(t0, plane0, ha), qb = end_uv(t1, plane1, hb);
  const double dx = qb.x - qa.x;
  const bool a_side = qa.x == 0.0, b_side = qb.x == 0.0;
  if (a_side || b_side) {
    if (dx == 0.0) return false;  // along the left side
    // The sweep's winding is higher right of an edge (right of an upward one: +1). Moving up past
    // an end on u = 0 crosses the edge from its right to its left where it goes in (dx > 0), the
    // reverse where it comes out: the sweep's winding just inside the side steps by −sign(dx),
    // the count of kept faces (its negative, close_left_side) by +sign(dx).
    const int step = dx > 0.0 ? 1 : -1;
    if (a_side) side.push_back({qa.y, step});
    if (b_side) side.push_back({qb.y, step});
  }
  uv.push_back({qa.x, qa.y, qb.x, qb.y});
  return true;
}

/// The left side's pieces (upward or downward copies along u = 0, one per kept face over them)
/// that make the winding field of `uv`'s clipped edges inside the square the kept faces' own:
/// the count along one ray from p to the side, stepped by the edges' ends there (`side`).
bool close_left_side(const EdgeSilhouetteQuery& q, std::vector<SideEvent>& side,
                     std::vector<UvEdge>& uv) {
  std::sort(side.begin(), side.end(),
            [](const SideEvent& a, const SideEvent& b) { return a.y < b.y; });
  // The ray goes into the widest gap between ends, else the next widest, at fractions of it
  // unrelated to the mesh's or the light's symmetries (a ray through an edge is unsure).
  struct Gap {
    double width, below;
  };
  thread_local std::vector<Gap> gaps;
  gaps.clear();
  double below = 0.0;
  for (const SideEvent& e : side) {
    const double y = std::clamp(e.y, 0.0, kUvScale);
    gaps.push_back({y - below, below});
    below = y;
  }
  gaps.push_back({kUvScale - below, below});
  std::sort(gaps.begin(), gaps.end(), [](const Gap& a, const Gap& b) { return a.width > b.width; });
  const ExactScene& scene = *q.scene;
  const auto& occluders = scene.occluders();
  int count = -1;
  double at = 0.0;
  constexpr double kFractions[3] = {0.41421356, 0.61803399, 0.29289322};
  for (size_t g = 0; g < std::min<size_t>(gaps.size(), 2) && count < 0; ++g) {
    for (int f = 0; f < 3 && count < 0 && gaps[g].width > 0.0; ++f) {
      at = gaps[g].below + kFractions[f] * gaps[g].width;
      const DVec3 seg = q.corner + (at / kUvScale) * q.edge_v - q.p;
      int crossed = 0;
      bool sure = true;
      scene.bvh().traverse(
          [&](const ExactBvh::Node& n) { return segment_meets_box(q.p, seg, n.lo, n.hi); },
          [&](uint32_t t) {
            const ExactOccluder& o = occluders[t];
            if (o.solid != q.solid) return true;
            const double side_p = glm::dot(o.normal, q.p - o.v[0]);
            if (q.keep_positive ? !(side_p > 0.0) : !(side_p < 0.0)) return true;
            const int c = signed_crossing(q.p, seg, o.v[0], o.v[1], o.v[2]);
            sure = c != kUnsure;
            crossed += c != 0 ? 1 : 0;
            return sure;
          });
      if (sure) count = crossed;
    }
  }
  if (count < 0) return false;
  // Each kept face over a point adds one positively oriented polygon: the sweep's winding there
  // (edges going up step it +1 left to right) is −1 per face, so the copies go down.
  int w = count;
  for (const SideEvent& e : side)
    if (e.y < at) w -= e.step;
  if (w < 0) return false;
  // Layer j (1, 2, …) covers the ordinates where at least j faces lie over the side: one edge per
  // run of each layer, so a constant count costs as many edges as faces, not per interval.
  thread_local std::vector<double> since;  // per layer: where its current run began
  since.assign(static_cast<size_t>(w), 0.0);
  const auto close = [&](size_t layer, double to) {
    const double from = std::clamp(since[layer], 0.0, kUvScale);
    to = std::clamp(to, 0.0, kUvScale);
    if (to > from) uv.push_back({0.0, to, 0.0, from});
  };
  for (const SideEvent& e : side) {
    const int next = w + e.step;
    if (next < 0) return false;
    for (int j = next; j < w; ++j) close(static_cast<size_t>(j), e.y);  // layers ending here
    since.resize(static_cast<size_t>(next), e.y);                       // or starting here
    w = next;
  }
  for (int j = 0; j < w; ++j) close(static_cast<size_t>(j), kUvScale);
  return true;
}

}  // namespace

bool append_edge_silhouette(const EdgeSilhouetteQuery& q, std::vector<UvEdge>& uv,
                            std::vector<uint32_t>& labels, uint64_t& searched) {
  const ExactScene& scene = *q.scene;
  const ExactSolid& solid = scene.solids()[q.solid];
  const ExactEdgeTree& tree = scene.edge_trees()[static_cast<size_t>(solid.edge_tree)];
  const LightProjection& proj = *q.proj;
  const auto kept = [&](uint32_t f) {
    const ExactFacePlane& face = tree.faces[f];
    const double side = glm::dot(face.normal, q.p - face.v0);
    return q.keep_positive ? side > 0.0 : side < 0.0;
  };
  thread_local std::vector<SideEvent> side;
  side.clear();
  const size_t first = uv.size();
  bool sure = true;
  tree.bvh.traverse_classified(
      [&](const ExactBvh::Node& n, bool inside) {
        const int c = inside ? ExactBvh::kInside : classify_box(proj, n.lo, n.hi);
        if (c == ExactBvh::kOutside || !sure) return ExactBvh::kOutside;
        const ExactNodeCone& cone = tree.cones[static_cast<size_t>(&n - tree.bvh.nodes().data())];
        // Every face below seen strictly from one side: every edge below cancels.
        if (cone.solid != ExactOccluder::kNotSolid &&
            (subtree_culled(cone, n, q.p, true) || subtree_culled(cone, n, q.p, false)))
          return ExactBvh::kOutside;
        return c;
      },
      [&](uint32_t e, bool) {
        ++searched;
        const ExactEdge& edge = tree.edges[e];
        const bool left = kept(edge.left);
        const bool right = edge.right != ExactOccluder::kNoNeighbour && kept(edge.right);
        if (left == right) return true;
        // The kept face's own direction along the edge, reversed where its projection is (as
        // exact_visibility orients each kept face: flip iff det M > 0 equals side > 0).
        const bool flip = q.det_positive == q.keep_positive;
        const bool forward = left != flip;
        sure = append_clipped(proj, forward ? edge.a : edge.b, forward ? edge.b : edge.a, uv, side);
        return sure;
      });
  if (sure) sure = close_left_side(q, side, uv);
  if (!sure) {
    uv.resize(first);
    return false;
  }
  labels.resize(uv.size(), q.label);
  return true;
}

}  // namespace penumbra
