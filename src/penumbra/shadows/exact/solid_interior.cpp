#include "penumbra/shadows/exact/solid_interior.hpp"

#include <algorithm>
#include <cmath>
#include <optional>
#include <utility>

#include "penumbra/core/parallel.hpp"
#include "penumbra/shadows/method.hpp"

namespace penumbra {

int signed_crossing(const DVec3& origin, const DVec3& seg, const DVec3& a, const DVec3& b,
                    const DVec3& c) {
  const DVec3 e1 = b - a, e2 = c - a;
  const DVec3 pvec = glm::cross(seg, e2);
  const double det = glm::dot(e1, pvec);
  const double scale = glm::length(e1) * glm::length(e2) * glm::length(seg);
  const DVec3 tvec = origin - a;
  if (!(std::abs(det) > 1e-12 * scale)) {
    // Nearly parallel: harmless unless the segment runs close to the triangle's plane.
    const DVec3 n = glm::cross(e1, e2);
    const double dist = std::abs(glm::dot(tvec, n)) / glm::length(n);
    return dist > 1e-9 * glm::length(seg) ? 0 : kUnsure;
  }
  const double inv = 1.0 / det;
  const double u = glm::dot(tvec, pvec) * inv;
  const DVec3 qvec = glm::cross(tvec, e1);
  const double v = glm::dot(seg, qvec) * inv;
  const double t = glm::dot(e2, qvec) * inv;
  constexpr double eps = 1e-9;
  if (u < -eps || v < -eps || u + v > 1.0 + eps || t < -eps || t > 1.0 + eps) return 0;
  if (u < eps || v < eps || u + v > 1.0 - eps || t < eps) return kUnsure;
  return det > 0.0 ? 1 : -1;  // det = −seg·n: positive when the segment goes against n
}

namespace {

/// The point of triangle (a, b, c) nearest to p, by the Voronoi regions of its vertices, edges and
/// face [Ericson 2004 §5.1.5].
DVec3 closest_on_triangle(const DVec3& p, const DVec3& a, const DVec3& b, const DVec3& c) {
  const DVec3 ab = b - a, ac = c - a, ap = p - a;
  const double d1 = glm::dot(ab, ap), d2 = glm::dot(ac, ap);
  if (d1 <= 0.0 && d2 <= 0.0) return a;
  const DVec3 bp = p - b;
  const double d3 = glm::dot(ab, bp), d4 = glm::dot(ac, bp);
  if (d3 >= 0.0 && d4 <= d3) return b;
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0) return a + (d1 / (d1 - d3)) * ab;
  const DVec3 cp = p - c;
  const double d5 = glm::dot(ab, cp), d6 = glm::dot(ac, cp);
  if (d6 >= 0.0 && d5 <= d6) return c;
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0) return a + (d2 / (d2 - d6)) * ac;
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0.0 && d4 - d3 >= 0.0 && d5 - d6 >= 0.0)
    return b + ((d4 - d3) / ((d4 - d3) + (d5 - d6))) * (c - b);
  const double denom = 1.0 / (va + vb + vc);
  return a + ab * (vb * denom) + ac * (vc * denom);
}

double box_distance2(const DVec3& p, const Vec3& lo, const Vec3& hi) {
  double d2 = 0.0;
  for (int i = 0; i < 3; ++i) {
    const double e = std::max({static_cast<double>(lo[i]) - p[i], 0.0, p[i] - hi[i]});
    d2 += e * e;
  }
  return d2;
}

/// The squared distance from p to solid s's surface or caps, looked for within `limit` of p
/// (limit² when nothing is that close). Nearer child first, so the bound tightens early.
double nearest_distance2(const ExactScene& scene, uint32_t s, const DVec3& p, double limit) {
  const auto& occluders = scene.occluders();
  const ExactSolid& solid = scene.solids()[s];
  double best2 = limit * limit;
  const auto consider = [&](const DVec3* v) {
    const DVec3 q = closest_on_triangle(p, v[0], v[1], v[2]);
    best2 = std::min(best2, glm::dot(q - p, q - p));
  };
  for (size_t k = 0; k < solid.caps.size(); ++k)
    if (box_distance2(p, solid.cap_triangle_boxes[k].lo, solid.cap_triangle_boxes[k].hi) < best2)
      consider(solid.caps[k].data());
  const auto& nodes = scene.bvh().nodes();
  const auto& prims = scene.bvh().primitives();
  if (nodes.empty()) return best2;
  struct Entry {
    uint32_t node;
    double d2;
  };
  std::array<Entry, ExactBvh::kMaxDepth + 2> stack;
  int top = 0;
  stack[top++] = {0, box_distance2(p, nodes[0].lo, nodes[0].hi)};
  while (top > 0) {
    const Entry e = stack[--top];
    if (!(e.d2 < best2)) continue;
    const ExactBvh::Node& n = nodes[e.node];
    if (n.count > 0) {
      for (uint32_t k = n.first; k < n.first + n.count; ++k) {
        const ExactOccluder& o = occluders[prims[k]];
        if (o.solid == s) consider(o.v);
      }
      continue;
    }
    const uint32_t l = e.node + 1, r = n.first;
    const double dl = box_distance2(p, nodes[l].lo, nodes[l].hi);
    const double dr = box_distance2(p, nodes[r].lo, nodes[r].hi);
    if (dl < dr) {
      stack[top++] = {r, dr};
      stack[top++] = {l, dl};
    } else {
      stack[top++] = {l, dl};
      stack[top++] = {r, dr};
    }
  }
  return best2;
}

}  // namespace

bool segment_meets_box(const DVec3& origin, const DVec3& dir, const Vec3& lo, const Vec3& hi) {
  double t0 = 0.0, t1 = 1.0;
  for (int i = 0; i < 3; ++i) {
    const double pad = 1e-9 * (std::abs(static_cast<double>(lo[i])) +
                               std::abs(static_cast<double>(hi[i])) + 1e-30);
    const double l = lo[i] - pad, h = hi[i] + pad;
    if (dir[i] == 0.0) {
      if (origin[i] < l || origin[i] > h) return false;
      continue;
    }
    const double inv = 1.0 / dir[i];
    double a = (l - origin[i]) * inv, b = (h - origin[i]) * inv;
    if (a > b) std::swap(a, b);
    t0 = std::max(t0, a);
    t1 = std::min(t1, b);
    if (t0 > t1) return false;
  }
  return true;
}

bool winding_number(const ExactScene& scene, uint32_t s, const DVec3& p, int& winding) {
  const ExactSolid& solid = scene.solids()[s];
  // Any fixed direction works; this one has no simple relation to axis-aligned or grid geometry.
  const DVec3 dir =
      glm::normalize(DVec3(0.5773502691896258, 0.6180339887498949, 0.5339082750072306));
  const double reach = glm::length(p - DVec3(solid.box.center())) + solid.box.diagonal();
  const DVec3 seg = (2.0 * reach) * dir;
  int crossings = 0;
  bool sure = true;
  for (const auto& cap : solid.caps) {
    const int c = signed_crossing(p, seg, cap[0], cap[1], cap[2]);
    if (c == kUnsure) return false;
    crossings += c;
  }
  const auto& occluders = scene.occluders();
  scene.bvh().traverse(
      [&](const ExactBvh::Node& n) { return sure && segment_meets_box(p, seg, n.lo, n.hi); },
      [&](uint32_t prim) {
        const ExactOccluder& o = occluders[prim];
        if (o.solid != s) return true;
        const int c = signed_crossing(p, seg, o.v[0], o.v[1], o.v[2]);
        if (c == kUnsure)
          sure = false;
        else
          crossings += c;
        return sure;
      });
  winding = -crossings;  // w(p) + Σ steps = w(far) = 0
  return sure;
}

namespace {

/// The voxel grid that ranks a solid's ball candidates: its box padded by one layer, `along`
/// voxels of side h along the box's longest side; dist per voxel: −1 inside (until the flood),
/// 0 on walls and outside, then the inside's chamfer distances.
struct VoxelGrid {
  double h;
  int n[3];
  DVec3 origin;
  size_t voxels;
  std::vector<int32_t> dist;

  VoxelGrid(const DVec3& box_lo, const DVec3& extent, double longest, size_t triangles) {
    const int along = std::clamp(static_cast<int>(8.0 * std::cbrt(static_cast<double>(triangles))),
                                 8, kInnerBallVoxels);
    h = longest / along;
    for (int a = 0; a < 3; ++a) n[a] = static_cast<int>(std::ceil(extent[a] / h - 1e-9)) + 3;
    origin = box_lo - DVec3(h);
    voxels = static_cast<size_t>(n[0]) * n[1] * n[2];
    dist.assign(voxels, -1);
  }
  size_t index(int x, int y, int z) const { return (static_cast<size_t>(z) * n[1] + y) * n[0] + x; }
  /// The voxel layers a triangle's box spans along axis a, first and last (unclamped).
  std::pair<double, double> span(const DVec3* v, int a) const {
    return std::pair{std::floor((std::min({v[0][a], v[1][a], v[2][a]}) - origin[a]) / h),
                     std::floor((std::max({v[0][a], v[1][a], v[2][a]}) - origin[a]) / h)};
  }
  /// The voxels a triangle's box spans.
  double box_voxels(const DVec3* v) const {
    double count = 1.0;
    for (int a = 0; a < 3; ++a) {
      const auto [first, last] = span(v, a);
      count *= last - first + 1.0;
    }
    return count;
  }
  /// Marks the voxels a triangle's box spans as walls.
  void wall(const DVec3* v) {
    int lo[3], hi[3];
    for (int a = 0; a < 3; ++a) {
      const auto [first, last] = span(v, a);
      // (Clamped off the border layer, which only rounding could reach.)
      lo[a] = std::clamp(static_cast<int>(first), 1, n[a] - 2);
      hi[a] = std::clamp(static_cast<int>(last), 1, n[a] - 2);
    }
    for (int z = lo[2]; z <= hi[2]; ++z)
      for (int y = lo[1]; y <= hi[1]; ++y)
        for (int x = lo[0]; x <= hi[0]; ++x) dist[index(x, y, z)] = 0;
  }
  /// Calls fn(w) for each voxel w sharing a face with voxel v.
  template <class F>
  void neighbours(size_t v, F&& fn) const {
    const int step[3] = {1, n[0], n[0] * n[1]};
    const int c[3] = {static_cast<int>(v % n[0]), static_cast<int>(v / n[0] % n[1]),
                      static_cast<int>(v / (static_cast<size_t>(n[0]) * n[1]))};
    for (int a = 0; a < 3; ++a) {
      if (c[a] > 0) fn(v - step[a]);
      if (c[a] + 1 < n[a]) fn(v + step[a]);
    }
  }
  DVec3 centre(size_t v) const {
    return origin + h * DVec3(static_cast<double>(v % n[0]) + 0.5,
                              static_cast<double>(v / n[0] % n[1]) + 0.5,
                              static_cast<double>(v / (static_cast<size_t>(n[0]) * n[1])) + 0.5);
  }
};

/// The walls: voxels touched by a triangle's box (surface and caps). Large triangles make many
/// walls: past a budget of voxel visits none are marked and the answer is false (the solid gets
/// no balls; they only save time).
bool mark_walls(VoxelGrid& grid, const ExactScene& scene, const ExactSolid& solid,
                std::span<const uint32_t> triangles) {
  double visits = 0.0;
  const auto& occluders = scene.occluders();
  for (const uint32_t t : triangles) visits += grid.box_voxels(occluders[t].v);
  for (const auto& cap : solid.caps) visits += grid.box_voxels(cap.data());
  if (!(visits <= 16.0 * static_cast<double>(grid.voxels))) return false;
  for (const uint32_t t : triangles) grid.wall(occluders[t].v);
  for (const auto& cap : solid.caps) grid.wall(cap.data());
  return true;
}

/// Outside: flood from a border voxel (the padding layer holds no wall).
void flood_outside(VoxelGrid& grid) {
  std::vector<size_t> queue{0};
  grid.dist[0] = 0;
  for (size_t head = 0; head < queue.size(); ++head)
    grid.neighbours(queue[head], [&](size_t w) {
      if (grid.dist[w] == -1) {
        grid.dist[w] = 0;
        queue.push_back(w);
      }
    });
}

/// Inside voxels by their chamfer distance (weights 3, 4, 5 for face, edge and corner steps:
/// within 8 % of Euclidean) to a wall or the outside, in two raster passes.
void chamfer_distances(VoxelGrid& grid) {
  constexpr int32_t kFar = 1 << 29;
  const int* n = grid.n;
  std::vector<int32_t>& dist = grid.dist;
  for (int32_t& d : dist) d = d == 0 ? 0 : kFar;
  // The 13 neighbours a forward raster pass has already visited, as index offsets and weights
  // (the backward pass uses their negatives). The border layer is outside, so only the interior
  // voxels are relaxed and every neighbour exists.
  std::array<std::ptrdiff_t, 13> offset;
  std::array<int32_t, 13> weight;
  int count = 0;
  for (int dz = -1; dz <= 0; ++dz)
    for (int dy = -1; dy <= 1; ++dy)
      for (int dx = -1; dx <= 1; ++dx) {
        if (dz == 0 && (dy > 0 || (dy == 0 && dx >= 0))) continue;
        offset[count] = (static_cast<std::ptrdiff_t>(dz) * n[1] + dy) * n[0] + dx;
        weight[count++] = 2 + (dx != 0) + (dy != 0) + (dz != 0);
      }
  const auto relax = [&](size_t v, int sign) {
    int32_t d = dist[v];
    if (d == 0) return;
    for (int k = 0; k < 13; ++k) d = std::min(d, dist[v + sign * offset[k]] + weight[k]);
    dist[v] = d;
  };
  for (int z = 1; z + 1 < n[2]; ++z)
    for (int y = 1; y + 1 < n[1]; ++y)
      for (int x = 1; x + 1 < n[0]; ++x) relax(grid.index(x, y, z), 1);
  for (int z = n[2] - 2; z >= 1; --z)
    for (int y = n[1] - 2; y >= 1; --y)
      for (int x = n[0] - 2; x >= 1; --x) relax(grid.index(x, y, z), -1);
}

/// The inside voxels, farthest first, ties in voxel order (deterministic): a counting sort by
/// distance.
std::vector<size_t> rank_inside(const VoxelGrid& grid) {
  const std::vector<int32_t>& dist = grid.dist;
  int32_t far = 0;
  for (const int32_t d : dist) far = std::max(far, d);
  std::vector<size_t> start(static_cast<size_t>(far) + 2, 0);
  for (const int32_t d : dist)
    if (d > 0) ++start[static_cast<size_t>(far - d) + 1];
  for (size_t k = 1; k < start.size(); ++k) start[k] += start[k - 1];
  std::vector<size_t> ranked(start.back());
  for (size_t v = 0; v < grid.voxels; ++v)
    if (dist[v] > 0) ranked[start[static_cast<size_t>(far - dist[v])]++] = v;
  return ranked;
}

bool covered(const std::vector<ExactInnerBall>& kept, const DVec3& c) {
  for (const ExactInnerBall& b : kept)
    if (glm::length(c - b.center) < b.radius) return true;
  return false;
}

/// The balls at the ranked voxels' centres: each one's distance to solid s's surface (less a
/// relative 1e-6, sought within `limit`), kept if the winding number there is non-zero. In
/// batches measured in parallel, accepted in rank order (deterministic), none with its centre
/// inside an accepted ball. Voxels next to a wall hold balls too small to hide a light; a budget
/// bounds the work: at most `most` balls, 4 · most measured, and measure_budget, which each
/// measure spends.
std::vector<ExactInnerBall> measure_balls(const ExactScene& scene, uint32_t s,
                                          const VoxelGrid& grid, const std::vector<size_t>& ranked,
                                          double limit, size_t most, size_t& measure_budget) {
  const auto measure = [&](const DVec3& c) -> std::optional<ExactInnerBall> {
    const double d2 = nearest_distance2(scene, s, c, limit);
    int w = 0;
    if (!(d2 > 0.0) || !winding_number(scene, s, c, w) || w == 0) return std::nullopt;
    return ExactInnerBall{c, std::sqrt(d2) * (1.0 - 1e-6)};
  };
  std::vector<ExactInnerBall> out;
  constexpr size_t kBatch = 16;
  size_t next = 0, measured = 0;
  const size_t allowed = std::min(4 * most, measure_budget);
  while (out.size() < most && measured < allowed) {
    std::vector<DVec3> batch;
    for (; next < ranked.size() && grid.dist[ranked[next]] >= 3 && batch.size() < kBatch; ++next)
      if (!covered(out, grid.centre(ranked[next]))) batch.push_back(grid.centre(ranked[next]));
    if (batch.empty()) break;
    measured += batch.size();
    measure_budget -= std::min(measure_budget, batch.size());
    std::vector<std::optional<ExactInnerBall>> balls(batch.size());
    parallel_chunks(batch.size(), 1, [&](size_t b0, size_t b1) {
      for (size_t k = b0; k < b1; ++k) balls[k] = measure(batch[k]);
    });
    std::stable_sort(balls.begin(), balls.end(), [](const auto& a, const auto& b) {
      return (a ? a->radius : -1.0) > (b ? b->radius : -1.0);
    });
    for (const auto& ball : balls)
      if (ball && out.size() < most && !covered(out, ball->center)) out.push_back(*ball);
  }
  return out;
}

}  // namespace

std::vector<ExactInnerBall> find_inner_balls(const ExactScene& scene, uint32_t s,
                                             std::span<const uint32_t> triangles,
                                             size_t& measure_budget) {
  const ExactSolid& solid = scene.solids()[s];
  const DVec3 box_lo(solid.box.lo), extent = DVec3(solid.box.hi) - box_lo;
  const double longest = std::max({extent.x, extent.y, extent.z});
  if (!(longest > 0.0) || !std::isfinite(longest)) return {};
  // No ball is wider than the box's narrowest side.
  const double limit = 0.5 * std::min({extent.x, extent.y, extent.z}) + 1e-12 * longest;

  // Candidates from a voxel grid: voxels touched by a triangle's box (surface and caps) are walls,
  // the others reachable from the padded border are outside, the rest inside, ranked by their
  // chamfer distance to a wall or the outside. Only the ranking comes from the voxels: every
  // kept ball is measured against the triangles and its winding number counted.
  VoxelGrid grid(box_lo, extent, longest, triangles.size());
  if (!mark_walls(grid, scene, solid, triangles)) return {};
  flood_outside(grid);
  chamfer_distances(grid);
  const std::vector<size_t> ranked = rank_inside(grid);
  // As many balls as triangles at most (a box needs no 128), 8 to kMaxInnerBalls.
  const size_t most = std::clamp<size_t>(triangles.size(), 8, kMaxInnerBalls);
  return measure_balls(scene, s, grid, ranked, limit, most, measure_budget);
}

std::vector<ExactBallGroup> group_inner_balls(std::vector<ExactInnerBall>& balls,
                                              const Bounds3& box) {
  const DVec3 lo(box.lo), extent = glm::max(DVec3(box.hi) - lo, DVec3(1e-300));
  const auto spread = [](uint32_t x) {  // 10 bits to every third of 30
    x &= 0x3FFu;
    x = (x | (x << 16)) & 0x030000FFu;
    x = (x | (x << 8)) & 0x0300F00Fu;
    x = (x | (x << 4)) & 0x030C30C3u;
    return (x | (x << 2)) & 0x09249249u;
  };
  std::vector<std::pair<uint32_t, uint32_t>> keyed(balls.size());
  for (size_t k = 0; k < balls.size(); ++k) {
    uint32_t code = 0;
    for (int a = 0; a < 3; ++a) {
      const double t = std::clamp((balls[k].center[a] - lo[a]) / extent[a], 0.0, 1.0);
      code |= spread(static_cast<uint32_t>(t * 1023.0)) << a;
    }
    keyed[k] = {code, static_cast<uint32_t>(k)};
  }
  std::sort(keyed.begin(), keyed.end());
  std::vector<ExactInnerBall> sorted(balls.size());
  for (size_t k = 0; k < balls.size(); ++k) sorted[k] = balls[keyed[k].second];
  balls.swap(sorted);
  std::vector<ExactBallGroup> groups;
  for (size_t first = 0; first < balls.size(); first += kBallGroup) {
    const size_t end = std::min(balls.size(), first + kBallGroup);
    DVec3 mid(0.0);
    for (size_t k = first; k < end; ++k) mid += balls[k].center;
    mid /= static_cast<double>(end - first);
    double radius = 0.0;
    for (size_t k = first; k < end; ++k)
      radius = std::max(radius, glm::length(balls[k].center - mid) + balls[k].radius);
    // Widened so that rounding never leaves a member poking out.
    groups.push_back({{mid, radius * (1.0 + 1e-9)},
                      static_cast<uint32_t>(first),
                      static_cast<uint32_t>(end - first)});
  }
  return groups;
}

namespace {

// Umbra without projection. Let a ball miss Z = M ∪ caps of solid S, with winding number w ≠ 0 over
// it (find_inner_balls), lie between p's plane parallel to the light and the light plane, and
// hold a point x of the segment p → q (q on the light). If w(q) = 0 and the segment misses the
// caps (cull_mode's premises in exact.cpp), then between x and q it crosses M at some y,
// transversally for all q but a set of measure zero. W grows along the segment, so
// W(y) > W(x) > kMinW; and y lies in S's box, which is farther from the light's box than the end
// margin of the shadow segment (1 − kShadowSegmentEnd of its length): y blocks q, and by the
// culling lemma (exact.cpp) so does a kept triangle. If that holds for every q, V = 0, as the area
// sweep would find to its rounding, with nothing projected.

/// The premises for solid s, beyond its balls: w(q) = 0 with the margin, and no segment p → q
/// meeting a cap (the pyramid misses every cap's box).
bool ball_premises(const ExactSolid& solid, const Bounds3& light_box, const LightProjection& proj,
                   double reach) {
  double gap = 0.0;
  for (int i = 0; i < 3; ++i)
    gap = std::max({gap, static_cast<double>(light_box.lo[i]) - solid.box.hi[i],
                    static_cast<double>(solid.box.lo[i]) - light_box.hi[i]});
  if (!(gap > 2.0 * (1.0 - kShadowSegmentEnd) * reach)) return false;
  if (!box_meets_pyramid(proj, solid.box.lo, solid.box.hi)) return false;  // no ball in the way
  for (const Bounds3& cap : solid.cap_boxes)
    if (box_meets_pyramid(proj, cap.lo, cap.hi)) return false;
  return true;
}

/// The light parallelogram as seen from p: a (kLattice + 1)² lattice of its points, relative to p,
/// in rows of v. Every light point lies in one of the kLattice² cells, and the directions from p
/// to a cell are the convex cone of its four corners' directions.
constexpr int kLattice = 6;
constexpr int kLatticePoints = (kLattice + 1) * (kLattice + 1);
static_assert(kLatticePoints <= 64);

}  // namespace

bool inner_balls_hide_light(const ExactScene& scene, const DVec3& p, const DVec3& corner,
                            const DVec3& edge_u, const DVec3& edge_v, const Bounds3& light_box,
                            const LightProjection& proj, std::span<const uint8_t> solid_met) {
  // The corners first (the light's cone); the rest of the lattice once a ball is in it.
  std::array<DVec3, kLatticePoints> to_light;
  std::array<double, kLatticePoints> length2;
  const auto lattice_point = [&](int i, int j) {
    const int k = j * (kLattice + 1) + i;
    to_light[k] = corner + (static_cast<double>(i) / kLattice) * edge_u +
                  (static_cast<double>(j) / kLattice) * edge_v - p;
    length2[k] = glm::dot(to_light[k], to_light[k]);
  };
  constexpr std::array<int, 4> kCorners = {0, kLattice, kLattice * (kLattice + 1),
                                           kLatticePoints - 1};
  for (const int k : kCorners) lattice_point(k % (kLattice + 1), k / (kLattice + 1));
  double reach2 = 0.0;
  for (const int k : kCorners) reach2 = std::max(reach2, length2[k]);
  const double reach = std::sqrt(reach2);  // the longest segment: convexity of the norm
  DVec3 normal = glm::normalize(glm::cross(edge_u, edge_v));
  double depth = glm::dot(corner - p, normal);
  if (depth < 0.0) normal = -normal, depth = -depth;
  // The light's cone of directions: around the centre's, within angle β (cos β ≤ every lattice
  // point's cosine; the cone is convex, so its extreme directions are corners).
  const DVec3 mid = glm::normalize(corner + 0.5 * (edge_u + edge_v) - p);
  double cos_beta = 1.0;
  for (const int k : kCorners)
    cos_beta = std::min(cos_beta, glm::dot(mid, to_light[k]) / std::sqrt(length2[k]));
  const double sin_beta = std::sqrt(std::max(0.0, 1.0 - cos_beta * cos_beta));

  constexpr uint64_t kAll = (uint64_t{1} << kLatticePoints) - 1u;
  uint64_t seen = 0;  // lattice points inside some ball's cone
  // The balls in the light's cone (the first 256): axis a = centre − p and |a|² − r².
  struct Relevant {
    DVec3 a;
    double k2;
  };
  std::array<Relevant, 256> relevant;
  size_t relevant_count = 0;
  std::array<uint64_t, 256> masks;
  size_t mask_count = 0;
  // Does the cone of directions from p into a ball (half-angle α, sin α = r/|a|) meet the light's:
  // angle(a, mid) < α + β? With |a|·cos α = √(|a|² − r²) and |a|·sin α = r, no division. A
  // group's bound holds its members, so their cones lie in its cone (p outside it) or p is inside
  // it (then its members are all tried).
  const auto meets_light = [&](const DVec3& a, double r) {
    const double a2 = glm::dot(a, a), r2 = r * r;
    if (!(a2 > r2)) return true;
    const double k = std::sqrt(a2 - r2);
    return glm::dot(a, mid) > k * cos_beta - r * sin_beta - 1e-9 * (k + r);
  };
  for (size_t s = 0; s < scene.solids().size(); ++s) {
    if (!solid_met.empty() && solid_met[s] == 0) continue;
    const ExactSolid& solid = scene.solids()[s];
    int premises = -1;  // unknown, checked at the solid's first ball in the light's cone
    for (const ExactBallGroup& group : solid.ball_groups) {
      if (!meets_light(group.bound.center - p, group.bound.radius)) continue;
      for (uint32_t b = group.first; b < group.first + group.count; ++b) {
        const ExactInnerBall& ball = solid.balls[b];
        const DVec3 a = ball.center - p;
        const double height = glm::dot(a, normal), r = ball.radius;
        if (!(height - r > 1e-6 * depth && height + r < depth)) continue;
        const double a2 = glm::dot(a, a), r2 = r * r;
        // A ball subtending under 1e-4 rad is left out: there the radius margin (1e-6) would no
        // longer dominate the cone test's rounding.
        if (!(r2 > 1e-8 * a2) || !meets_light(a, r)) continue;
        if (premises < 0) premises = ball_premises(solid, light_box, proj, reach) ? 1 : 0;
        if (premises == 0) break;
        if (relevant_count < relevant.size()) relevant[relevant_count++] = {a, a2 - r2};
      }
      if (premises == 0) break;
    }
  }
  // A direction inside a ball's cone: angle to its axis a below asin(r/|a|), k2 = |a|² − r² > 0
  // (p lies outside: height > r).
  const auto inside = [&](const Relevant& b, int k) {
    const double t = glm::dot(to_light[k], b.a);
    return t > 0.0 && t * t > length2[k] * b.k2;
  };
  // The corners and the centre first: most receivers in penumbra see one of them.
  constexpr int kCentre = (kLattice / 2) * (kLattice + 2);
  lattice_point(kLattice / 2, kLattice / 2);
  for (const int k : {kCorners[0], kCorners[1], kCorners[2], kCorners[3], kCentre}) {
    bool hit = false;
    for (size_t m = 0; m < relevant_count && !hit; ++m) hit = inside(relevant[m], k);
    if (!hit) return false;
  }
  for (int j = 0; j <= kLattice; ++j)
    for (int i = 0; i <= kLattice; ++i) lattice_point(i, j);
  for (size_t m = 0; m < relevant_count; ++m) {
    uint64_t mask = 0;
    for (int k = 0; k < kLatticePoints; ++k)
      mask |= static_cast<uint64_t>(inside(relevant[m], k)) << k;
    if (mask == kAll) return true;
    seen |= mask;
    masks[mask_count++] = mask;
  }
  if (seen != kAll) return false;
  // Every cell inside one ball's cone (its four corners in one mask).
  for (int j = 0; j < kLattice; ++j)
    for (int i = 0; i < kLattice; ++i) {
      const int k = j * (kLattice + 1) + i;
      const uint64_t one = 1;
      const uint64_t cell =
          (one << k) | (one << (k + 1)) | (one << (k + kLattice + 1)) | (one << (k + kLattice + 2));
      bool covered = false;
      for (size_t m = 0; m < mask_count && !covered; ++m) covered = (masks[m] & cell) == cell;
      if (!covered) return false;
    }
  return true;
}

}  // namespace penumbra
