#include "penumbra/shadows/exact/projection.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <tuple>

#include "penumbra/shadows/exact/bvh.hpp"
#include "penumbra/shadows/method.hpp"

namespace penumbra {

namespace {

using ClipperLib::cInt;
using ClipperLib::IntPoint;
using ClipperLib::Path;
using ClipperLib::Paths;

uint64_t splitmix(uint64_t x) {
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ull;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebull;
  return x ^ (x >> 31);
}

cInt to_clipper(double uv) {
  // llround of a value ≥ 0 (half away from zero), without the library call: x − floor(x) is
  // exact in floating point.
  const double x = std::clamp(uv, 0.0, 1.0) * kUvScale;
  const double f = std::floor(x);
  return static_cast<cInt>(f) + (x - f >= 0.5 ? 1 : 0);
}

/// Sutherland–Hodgman against one axis-aligned half-plane: keeps points with
/// sign · (coordinate[axis] − bound) ≥ 0.
void clip_axis(const std::vector<DVec2>& in, std::vector<DVec2>& out, int axis, double bound,
               double sign) {
  out.clear();
  const size_t n = in.size();
  if (n == 0) return;
  for (size_t i = 0; i < n; ++i) {
    const DVec2& prev = in[(i + n - 1) % n];
    const DVec2& cur = in[i];
    const double fp = sign * (prev[axis] - bound);
    const double fc = sign * (cur[axis] - bound);
    if ((fc >= 0.0) != (fp >= 0.0)) {
      const double t = fp / (fp - fc);
      DVec2 x = prev + t * (cur - prev);
      x[axis] = bound;  // exactly on the window edge, whatever the rounding of t
      out.push_back(x);
    }
    if (fc >= 0.0) out.push_back(cur);
  }
}

double shoelace(const std::vector<DVec2>& poly) {
  double twice = 0.0;
  const size_t n = poly.size();
  for (size_t i = 0; i < n; ++i) {
    const DVec2& a = poly[i];
    const DVec2& b = poly[(i + 1) % n];
    twice += a.x * b.y - a.y * b.x;
  }
  return 0.5 * twice;
}

void to_uv(const Path& path, std::vector<DVec2>& out) {
  out.clear();
  for (const IntPoint& q : path)
    out.emplace_back(static_cast<double>(q.X) / kUvScale, static_cast<double>(q.Y) / kUvScale);
}

/// Removes, in place, every vertex of a closed loop that lies on the line through its neighbours
/// (exact integer cross product: coordinates are below 2^31, so it fits 64 bits). The winding
/// number changes only on those lines, a set of measure zero: the loop's union area is the same.
/// Mostly the runs of pieces along the light's sides, one per clipped triangle, which would
/// otherwise cost the union a scanbeam each.
void drop_collinear(Path& loop) {
  const auto collinear = [](const IntPoint& a, const IntPoint& b, const IntPoint& c) {
    return (b.X - a.X) * (c.Y - a.Y) == (b.Y - a.Y) * (c.X - a.X);
  };
  size_t n = loop.size();
  if (n < 3) return;
  size_t out = 0;
  for (size_t i = 0; i < n; ++i) {
    // Compare against the last vertex kept (or the loop's last one for the first vertex).
    const IntPoint& prev = out > 0 ? loop[out - 1] : loop[n - 1];
    const IntPoint& next = loop[i + 1 < n ? i + 1 : 0];
    if (collinear(prev, loop[i], next)) continue;
    loop[out++] = loop[i];
  }
  loop.resize(out);
  // The wrap-around: the first kept vertices may have become collinear with the last ones.
  while (loop.size() >= 3 && collinear(loop[loop.size() - 2], loop.back(), loop[0]))
    loop.pop_back();
  while (loop.size() >= 3 && collinear(loop.back(), loop[0], loop[1])) loop.erase(loop.begin());
}

}  // namespace

bool make_light_projection(const DVec3& receiver, const DVec3& corner, const DVec3& edge_u,
                           const DVec3& edge_v, LightProjection& out) {
  const DVec3 cross = glm::cross(edge_u, edge_v);
  const double cross_len = glm::length(cross);
  const double size = std::max(glm::length(edge_u), glm::length(edge_v));
  if (!(cross_len > 1e-12 * size * size) || !std::isfinite(cross_len)) return false;
  const DVec3 n = cross / cross_len;
  const double D = glm::dot(corner - receiver, n);
  if (!(std::abs(D) > 1e-9 * size)) return false;  // receiver in the light's plane (or NaN)

  // Dual basis of (edge_u, edge_v) from the inverse Gram matrix; det = |edge_u × edge_v|².
  const double g00 = glm::dot(edge_u, edge_u), g01 = glm::dot(edge_u, edge_v),
               g11 = glm::dot(edge_v, edge_v);
  const double det = cross_len * cross_len;
  const DVec3 a = (g11 * edge_u - g01 * edge_v) / det;
  const DVec3 b = (g00 * edge_v - g01 * edge_u) / det;

  out.origin = receiver;
  out.to_w = n / D;
  out.to_u = a + glm::dot(receiver - corner, a) * out.to_w;
  out.to_v = b + glm::dot(receiver - corner, b) * out.to_w;

  // The six faces of the pyramid, as linear inequalities in x − p: −U ≤ 0, U − W ≤ 0 (the side
  // planes through p and the edges u = 0, u = 1), the same for V, W ≤ 1 (the light plane) and
  // −W ≤ 0 (the plane through p parallel to the light).
  const DVec3 normals[6] = {
      -out.to_u, out.to_u - out.to_w, -out.to_v, out.to_v - out.to_w, out.to_w, -out.to_w};
  const double offsets[6] = {0.0, 0.0, 0.0, 0.0, 1.0, 0.0};
  for (int k = 0; k < 6; ++k) {
    out.planes[k].n = normals[k];
    out.planes[k].d = offsets[k] + glm::dot(normals[k], receiver);
  }
  // The clip half-spaces of project_polygon, in its order (f ≥ 0).
  out.clip_n = {out.to_w, -out.to_w, out.to_u, out.to_w - out.to_u, out.to_v, out.to_w - out.to_v};
  out.clip_c = {-kMinW, kShadowSegmentEnd, 0.0, 0.0, 0.0, 0.0};
  LightProjection::Lanes& l = out.lanes;
  for (int k = 0; k < 8; ++k) {
    const DVec3 n = k < 6 ? out.clip_n[k] : DVec3(0.0);
    const double c = k < 6 ? out.clip_c[k] : 1.0;
    l.nx[k] = n.x;
    l.ny[k] = n.y;
    l.nz[k] = n.z;
    l.c[k] = c;
    l.ax[k] = std::abs(n.x);
    l.ay[k] = std::abs(n.y);
    l.az[k] = std::abs(n.z);
    l.ac[k] = std::abs(c);
  }
  return true;
}

bool box_meets_pyramid(const LightProjection& proj, const Vec3& lo, const Vec3& hi) {
  for (const LightProjection::Plane& plane : proj.planes) {
    double min_dot = 0.0, magnitude = std::abs(plane.d);
    for (int i = 0; i < 3; ++i) {
      const double c = plane.n[i] >= 0.0 ? lo[i] : hi[i];
      min_dot += plane.n[i] * c;
      magnitude += std::abs(plane.n[i]) * std::max(std::abs(static_cast<double>(lo[i])),
                                                   std::abs(static_cast<double>(hi[i])));
    }
    // The relative tolerance keeps the test conservative under rounding (never culls a box that
    // touches the pyramid).
    if (min_dot > plane.d + 1e-9 * magnitude) return false;
  }
  return true;
}

int classify_box(const LightProjection& proj, const Vec3& lo, const Vec3& hi) {
  // Against project_polygon's own six half-spaces f_k ≥ 0: a box with f_k < 0 throughout for one
  // k holds nothing the clip keeps (tighter than box_meets_pyramid, which stops at W = 0 and 1).
  // Both ends carry a relative margin of 1e-9, far above the rounding of either computation.
  // Eight lanes without branches, so the compiler vectorises the loop.
  // Centre and half extent: f at the centre ± Σ |n_i|·extent_i bound f over the box (their
  // rounding in double is far below the margin).
  const double cx = 0.5 * (static_cast<double>(lo.x) + hi.x) - proj.origin.x;
  const double cy = 0.5 * (static_cast<double>(lo.y) + hi.y) - proj.origin.y;
  const double cz = 0.5 * (static_cast<double>(lo.z) + hi.z) - proj.origin.z;
  const double ex = 0.5 * (static_cast<double>(hi.x) - lo.x);
  const double ey = 0.5 * (static_cast<double>(hi.y) - lo.y);
  const double ez = 0.5 * (static_cast<double>(hi.z) - lo.z);
  const double bx = std::abs(cx) + ex, by = std::abs(cy) + ey, bz = std::abs(cz) + ez;
  const LightProjection::Lanes& l = proj.lanes;
  int outside = 0, inside = 0;
  for (int k = 0; k < 8; ++k) {
    const double f = l.c[k] + l.nx[k] * cx + l.ny[k] * cy + l.nz[k] * cz;
    const double r = l.ax[k] * ex + l.ay[k] * ey + l.az[k] * ez;
    const double margin = 1e-9 * (l.ac[k] + l.ax[k] * bx + l.ay[k] * by + l.az[k] * bz);
    outside |= f + r < -margin ? 1 : 0;
    inside += f - r > margin ? 1 : 0;
  }
  if (outside) return ExactBvh::kOutside;
  return inside == 8 ? ExactBvh::kInside : ExactBvh::kPartial;
}

void clip_polygon(const LightProjection& proj, const DVec3* vertices, int count,
                  ClippedPolygon& out) {
  out.n = 0;
  if (count < 3 || count > kMaxPolygon) return;
  DVec3 h[kMaxPolygon];
  for (int i = 0; i < count; ++i) h[i] = proj.homogeneous(vertices[i]);
  clip_homogeneous(h, count, out);
}

int classify_homogeneous(const DVec3* h, int count) {
  // Per plane the number of vertices failing it (the plane loop unrolls: no switch is left).
  int fails[6] = {0, 0, 0, 0, 0, 0};
  for (int i = 0; i < count; ++i)
    for (int plane = 0; plane < 6; ++plane) fails[plane] += clip_value(plane, h[i]) >= 0.0 ? 0 : 1;
  int any = 0;
  for (int plane = 0; plane < 6; ++plane) {
    if (fails[plane] == count) return ExactBvh::kOutside;
    any += fails[plane];
  }
  return any == 0 ? ExactBvh::kInside : ExactBvh::kPartial;
}

void clip_homogeneous(const DVec3* h, int count, ClippedPolygon& out) {
  out.n = 0;
  if (count < 3 || count > kMaxPolygon) return;
  constexpr int kCapacity = ClippedPolygon::kCapacity;
  DVec3 buf_a[kCapacity], buf_b[kCapacity];
  int8_t edge_a[kCapacity], edge_b[kCapacity];
  DVec3* in = buf_a;
  DVec3* next = buf_b;
  int8_t* in_edge = edge_a;
  int8_t* next_edge = edge_b;
  int n = count;
  for (int i = 0; i < count; ++i) {
    in[i] = h[i];
    in_edge[i] = static_cast<int8_t>(i);
  }

  for (int plane = 0; plane < 6 && n > 0; ++plane) {
    int m = 0;
    bool all_inside = true;
    double fv[kCapacity];
    for (int i = 0; i < n; ++i) {
      fv[i] = clip_value(plane, in[i]);
      all_inside &= fv[i] >= 0.0;
    }
    if (all_inside) continue;
    for (int i = 0; i < n; ++i) {
      const int j = (i + n - 1) % n;  // previous vertex
      if ((fv[i] >= 0.0) != (fv[j] >= 0.0)) {
        // Interpolate from the lexicographically smaller end: an edge shared by two polygons
        // (traversed in opposite directions) then clips to bit-identical points, so its two
        // copies still cancel.
        const bool j_first =
            std::tie(in[j].x, in[j].y, in[j].z) < std::tie(in[i].x, in[i].y, in[i].z);
        const int a = j_first ? j : i, b = j_first ? i : j;
        const double t = fv[a] / (fv[a] - fv[b]);
        next[m] = in[a] + t * (in[b] - in[a]);
        // Entering (j outside): the rest of the edge j → i follows. Leaving: the next point is
        // where the polygon re-enters, along this plane.
        next_edge[m++] = fv[i] >= 0.0 ? in_edge[j] : ClippedPolygon::kClipEdge;
      }
      if (fv[i] >= 0.0) {
        next[m] = in[i];
        next_edge[m++] = in_edge[i];
      }
    }
    std::swap(in, next);
    std::swap(in_edge, next_edge);
    n = m;
  }
  out.n = n;
  for (int i = 0; i < n; ++i) {
    const DVec3& h = in[i];
    out.q[i] = IntPoint(to_clipper(h.x / h.z), to_clipper(h.y / h.z));
    out.edge[i] = in_edge[i];
  }
}

bool project_polygon(const LightProjection& proj, const DVec3* vertices, int count,
                     ClipperLib::Path& out) {
  out.clear();
  ClippedPolygon clipped;
  clip_polygon(proj, vertices, count, clipped);
  if (clipped.n < 3) return false;
  out.reserve(clipped.n);
  for (int i = 0; i < clipped.n; ++i) {
    if (!out.empty() && out.back() == clipped.q[i]) continue;
    out.push_back(clipped.q[i]);
  }
  while (out.size() > 1 && out.back() == out.front()) out.pop_back();
  if (out.size() < 3) {
    out.clear();
    return false;
  }
  const double area = ClipperLib::Area(out);
  if (area == 0.0) {
    out.clear();
    return false;
  }
  // One orientation for every input polygon: under the non-zero fill rule two overlapping
  // polygons of opposite orientation would cancel to a hole.
  if (area < 0.0) std::reverse(out.begin(), out.end());
  return true;
}

LightOutline make_light_outline(bool round, int disk_segments) {
  LightOutline o;
  o.round = round;
  const cInt s = static_cast<cInt>(kUvScale);
  if (!round) {
    o.path = {IntPoint(0, 0), IntPoint(s, 0), IntPoint(s, s), IntPoint(0, s)};
    o.area = ClipperLib::Area(o.path);
    return o;
  }
  // A round light (disk, sphere silhouette) emits inside the circle C of radius r = 0.5 at
  // (0.5, 0.5). Clipper needs polygons, so C is replaced by the regular N-gon P of the same area:
  // circumradius R = r·sqrt(2π / (N·sin(2π/N))).
  // Error bound, with h = π/N: to second order P's boundary lies radially between −r·h²/6 (edge
  // midpoints) and +r·h²/3 (vertices) of C's. Crudely, |P Δ C| ≤ perimeter · r·h²/3, so the
  // visible fraction moves by at most 2h²/3 (1.0e-4 for N = 256). Integrating the deviation over
  // each edge is sharper: |P ∖ C| = |C ∖ P| = 2h²/(9√3) · |C|. For a blocked set U,
  // V_C = 1 − |U ∩ C|/|C| and V_P = 1 − |U ∩ P|/|P| with |P| = |C| differ by
  // |U ∩ (C ∖ P)| − |U ∩ (P ∖ C)|, whose magnitude is at most |C ∖ P|, hence
  //   |V_P − V_C| ≤ 2h²/(9√3) ≈ 0.128·(π/N)²:  1.9e-5 for N = 256 (3.1e-4 for N = 64,
  //   4.8e-6 for N = 512).
  // We divide by P's own (rounded) area, so V_P is exact for P. The vertices sit at angles
  // (2k+1)π/N: for N a multiple of 4 the extreme points along u and v are edge midpoints at the
  // apothem R·cos(h) < r, so P stays inside the uv square the occluder polygons are clipped to
  // (other N: the few vertices that stick out, by at most r·h²/3, are clamped onto the square).
  const int n = std::max(3, disk_segments);
  const double r = 0.5;
  const double h = kPi / n;
  const double R = r * std::sqrt(2.0 * kPi / (n * std::sin(2.0 * h)));
  o.path.reserve(n);
  for (int k = 0; k < n; ++k) {
    const double theta = (2 * k + 1) * h;
    const IntPoint q(to_clipper(0.5 + R * std::cos(theta)), to_clipper(0.5 + R * std::sin(theta)));
    if (!o.path.empty() && o.path.back() == q) continue;
    o.path.push_back(q);
  }
  o.area = ClipperLib::Area(o.path);
  return o;
}

double paths_area(const Paths& paths) {
  double a = 0.0;
  for (const Path& p : paths) a += ClipperLib::Area(p);
  return a;
}

void append_polygon_edges(std::span<const Path> polygons, std::vector<DirectedEdge>& edges) {
  for (const Path& p : polygons)
    for (size_t i = 0; i < p.size(); ++i) edges.push_back({p[i], p[(i + 1) % p.size()]});
}

Paths cancel_shared_edges(std::span<const Path> polygons) {
  std::vector<DirectedEdge> edges;
  append_polygon_edges(polygons, edges);
  Paths loops;
  loops.resize(trace_loops(edges, loops));
  return loops;
}

namespace {

/// Removes every pair of opposite copies of one segment from `edges` (and zero-length edges).
void cancel_opposite_edges(std::vector<DirectedEdge>& edges) {
  // Net multiplicity of every undirected segment (+1 per lo→hi copy, −1 per hi→lo), in an
  // open-addressing hash table: linear in the edge count (a sort was half of a penumbra pixel's
  // time). Points pack into 64 bits since coordinates are in [0, 2^30). The table is reused per
  // thread and only the slots a call used are reset, so a call costs its edges, not the table.
  // 24-byte slots keyed by the packed end points (coordinates are in [0, 2^30), so X·2^32 + Y is
  // exact and 0 is never a valid pair of distinct points: it marks an empty slot).
  struct Slot {
    uint64_t lo = 0, hi = 0;
    int64_t net = 0;
  };
  size_t capacity = 16;
  while (capacity < 2 * edges.size()) capacity *= 2;
  thread_local std::vector<Slot> table;
  thread_local std::vector<size_t> used;
  if (table.size() < capacity) table.assign(capacity, Slot{});
  used.clear();
  const auto pack = [](const IntPoint& q) {
    return (static_cast<uint64_t>(q.X) << 32) | static_cast<uint64_t>(q.Y);
  };
  for (const DirectedEdge& e : edges) {
    if (e.from == e.to) continue;
    const uint64_t ka = pack(e.from), kb = pack(e.to);
    const bool forward = ka < kb;
    const uint64_t lo = forward ? ka : kb, hi = forward ? kb : ka;
    size_t h = static_cast<size_t>(splitmix(lo * 0x9e3779b97f4a7c15ull ^ hi)) & (capacity - 1);
    while (table[h].hi != 0 && !(table[h].lo == lo && table[h].hi == hi))
      h = (h + 1) & (capacity - 1);
    Slot& slot = table[h];
    if (slot.hi == 0) {  // hi > lo ≥ 0, so an occupied slot has hi ≠ 0
      slot.lo = lo;
      slot.hi = hi;
      used.push_back(h);
    }
    slot.net += forward ? 1 : -1;
  }
  // The surviving directed edges (edges is reused for them).
  std::vector<DirectedEdge>& kept = edges;
  kept.clear();
  const auto unpack = [](uint64_t k) {
    return IntPoint(static_cast<cInt>(k >> 32), static_cast<cInt>(k & 0xFFFFFFFFull));
  };
  for (const size_t h : used) {
    Slot& slot = table[h];
    const IntPoint lo = unpack(slot.lo), hi = unpack(slot.hi);
    for (int64_t k = 0; k < std::abs(slot.net); ++k)
      kept.push_back(slot.net > 0 ? DirectedEdge{lo, hi} : DirectedEdge{hi, lo});
    slot = Slot{};
  }
}

}  // namespace

size_t trace_loops(std::vector<DirectedEdge>& edges, Paths& loops, bool cancel) {
  constexpr uint64_t kNoPoint = ~uint64_t{0};  // never a packed point: coordinates are < 2^31
  constexpr uint32_t kNoEdge = ~uint32_t{0};
  const auto pack = [](const IntPoint& q) {
    return (static_cast<uint64_t>(q.X) << 32) | static_cast<uint64_t>(q.Y);
  };
  thread_local std::vector<size_t> used;
  if (cancel) {
    cancel_opposite_edges(edges);
  } else {
    edges.erase(std::remove_if(edges.begin(), edges.end(),
                               [](const DirectedEdge& e) { return e.from == e.to; }),
                edges.end());
  }
  std::vector<DirectedEdge>& kept = edges;
  // Trace closed walks. Every vertex has as many kept edges in as out (each chain is closed and
  // a cancelled pair removes one of each), so a walk can always leave any vertex it entered and
  // must end where it started. The edges leaving each point form a list (head in a second hash
  // table keyed by the point, links in `next`), consumed in input order.
  struct Head {
    uint64_t point = kNoPoint;
    uint32_t first = 0;
  };
  thread_local std::vector<Head> heads;
  thread_local std::vector<uint32_t> next;
  size_t head_capacity = 16;
  while (head_capacity < 2 * kept.size()) head_capacity *= 2;
  if (heads.size() < head_capacity) heads.assign(head_capacity, Head{});
  next.resize(kept.size());
  const auto find_head = [&](uint64_t point) -> size_t {
    size_t h = static_cast<size_t>(splitmix(point)) & (head_capacity - 1);
    while (heads[h].point != kNoPoint && heads[h].point != point) h = (h + 1) & (head_capacity - 1);
    return h;
  };
  used.clear();
  for (size_t i = kept.size(); i-- > 0;) {
    const size_t h = find_head(pack(kept[i].from));
    Head& head = heads[h];
    if (head.point == kNoPoint) {
      used.push_back(h);
      next[i] = kNoEdge;
    } else {
      next[i] = head.first;
    }
    head.point = pack(kept[i].from);
    head.first = static_cast<uint32_t>(i);
  }
  size_t count = 0;
  for (size_t i = 0; i < kept.size(); ++i) {
    if (heads[find_head(pack(kept[i].from))].first == kNoEdge)
      continue;  // every edge leaving this point is used
    if (loops.size() == count) loops.emplace_back();
    Path& loop = loops[count];
    loop.clear();
    const IntPoint start = kept[i].from;
    IntPoint at = start;
    do {
      loop.push_back(at);
      Head& head = heads[find_head(pack(at))];
      if (head.point == kNoPoint || head.first == kNoEdge) break;  // unreachable: chains close
      const uint32_t e = head.first;
      head.first = next[e];
      at = kept[e].to;
    } while (at != start);
    drop_collinear(loop);
    if (loop.size() >= 3) ++count;
  }
  for (const size_t h : used) heads[h] = Head{};
  return count;
}

Paths union_polygons(const Paths& polygons, size_t group) {
  group = std::max<size_t>(group, 2);
  std::vector<Paths> level;
  level.reserve(polygons.size() / group + 1);
  for (size_t i = 0; i < polygons.size(); i += group) {
    ClipperLib::Clipper c;
    for (size_t k = i; k < std::min(polygons.size(), i + group); ++k)
      c.AddPath(polygons[k], ClipperLib::ptSubject, true);
    level.emplace_back();
    c.Execute(ClipperLib::ctUnion, level.back(), ClipperLib::pftNonZero, ClipperLib::pftNonZero);
  }
  while (level.size() > 1) {
    std::vector<Paths> next;
    next.reserve(level.size() / 2 + 1);
    for (size_t i = 0; i < level.size(); i += 2) {
      if (i + 1 == level.size()) {
        next.push_back(std::move(level[i]));
        continue;
      }
      ClipperLib::Clipper c;
      c.AddPaths(level[i], ClipperLib::ptSubject, true);
      c.AddPaths(level[i + 1], ClipperLib::ptClip, true);
      next.emplace_back();
      c.Execute(ClipperLib::ctUnion, next.back(), ClipperLib::pftNonZero, ClipperLib::pftNonZero);
    }
    level.swap(next);
  }
  return level.empty() ? Paths{} : std::move(level[0]);
}

std::vector<LightRegion> visible_regions(const LightOutline& outline,
                                         std::span<const Path> opaque_loops,
                                         const std::vector<SemiPolygon>& semi) {
  std::vector<LightRegion> regions(1);
  if (opaque_loops.empty()) {
    regions[0].paths = {outline.path};
  } else {
    ClipperLib::Clipper c;
    c.AddPath(outline.path, ClipperLib::ptSubject, true);
    if (opaque_loops.size() <= kUnionGroup) {
      for (const Path& loop : opaque_loops) c.AddPath(loop, ClipperLib::ptClip, true);
    } else {
      c.AddPaths(union_polygons(Paths(opaque_loops.begin(), opaque_loops.end()), kUnionGroup),
                 ClipperLib::ptClip, true);
    }
    c.Execute(ClipperLib::ctDifference, regions[0].paths, ClipperLib::pftNonZero,
              ClipperLib::pftNonZero);
  }
  if (regions[0].paths.empty() || semi.empty())
    return regions[0].paths.empty() ? std::vector<LightRegion>{} : regions;

  // Groups of equal transmittance, in order of first appearance (deterministic).
  std::vector<double> values;
  for (const SemiPolygon& p : semi)
    if (std::find(values.begin(), values.end(), p.transmittance) == values.end())
      values.push_back(p.transmittance);

  const cInt s = static_cast<cInt>(kUvScale);
  const Path reversed_square = {IntPoint(0, 0), IntPoint(0, s), IntPoint(s, s), IntPoint(s, 0)};
  Paths group;
  for (const double t : values) {
    group.clear();
    for (const SemiPolygon& p : semi)
      if (p.transmittance == t) group.push_back(p.path);
    const Paths loops = group.size() > 1 ? cancel_shared_edges(group) : group;
    const size_t count = regions.size();
    for (size_t r = 0; r < count; ++r) {
      double scale = 1.0;  // t^(k−1)
      for (size_t k = 1; k <= group.size(); ++k) {
        ClipperLib::Clipper c;
        c.AddPaths(loops, ClipperLib::ptSubject, true);
        for (size_t copy = 1; copy < k; ++copy)
          c.AddPath(reversed_square, ClipperLib::ptSubject, true);
        c.AddPaths(regions[r].paths, ClipperLib::ptClip, true);
        LightRegion level;
        c.Execute(ClipperLib::ctIntersection, level.paths, ClipperLib::pftPositive,
                  ClipperLib::pftNonZero);
        if (level.paths.empty()) break;  // no point is covered k times
        level.weight = -regions[r].weight * (1.0 - t) * scale;
        regions.push_back(std::move(level));
        scale *= t;
        if (scale < 1e-12) break;
      }
    }
  }
  return regions;
}

DVec3 texel_weighted_area(const Paths& paths, int width, int height,
                          const std::vector<DVec3>& texel_weight) {
  DVec3 sum(0.0);
  std::vector<DVec2> poly, row, tmp, cell;
  for (const Path& path : paths) {
    to_uv(path, poly);
    if (poly.size() < 3) continue;
    double vmin = poly[0].y, vmax = poly[0].y;
    for (const DVec2& q : poly) {
      vmin = std::min(vmin, q.y);
      vmax = std::max(vmax, q.y);
    }
    const int ty0 = std::clamp(static_cast<int>(std::floor(vmin * height)), 0, height - 1);
    const int ty1 = std::clamp(static_cast<int>(std::floor(vmax * height)), 0, height - 1);
    for (int ty = ty0; ty <= ty1; ++ty) {
      // Strip [ty/h, (ty+1)/h]; the last strip reaches v = 1 exactly.
      clip_axis(poly, tmp, 1, static_cast<double>(ty) / height, 1.0);
      clip_axis(tmp, row, 1, static_cast<double>(ty + 1) / height, -1.0);
      if (row.size() < 3) continue;
      double umin = row[0].x, umax = row[0].x;
      for (const DVec2& q : row) {
        umin = std::min(umin, q.x);
        umax = std::max(umax, q.x);
      }
      const int tx0 = std::clamp(static_cast<int>(std::floor(umin * width)), 0, width - 1);
      const int tx1 = std::clamp(static_cast<int>(std::floor(umax * width)), 0, width - 1);
      for (int tx = tx0; tx <= tx1; ++tx) {
        double area = 0.0;
        if (tx0 == tx1) {
          area = shoelace(row);
        } else {
          clip_axis(row, tmp, 0, static_cast<double>(tx) / width, 1.0);
          clip_axis(tmp, cell, 0, static_cast<double>(tx + 1) / width, -1.0);
          if (cell.size() >= 3) area = shoelace(cell);
        }
        if (area != 0.0) sum += area * texel_weight[static_cast<size_t>(ty) * width + tx];
      }
    }
  }
  return sum;
}

}  // namespace penumbra
