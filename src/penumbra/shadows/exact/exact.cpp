// `exact`: the per-point analytic visibility and the ShadowMethod around it.
#include "penumbra/shadows/exact/exact.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <memory>

#include "penumbra/core/parallel.hpp"
#include "penumbra/core/progress.hpp"
#include "penumbra/render/receivers.hpp"
#include "penumbra/shadows/exact/edge_tree.hpp"
#include "penumbra/shadows/exact/solid_interior.hpp"
#include "penumbra/shadows/exact/union_area.hpp"
#include "penumbra/shadows/registry.hpp"

namespace penumbra {

namespace {

using ClipperLib::cInt;

/// Open projections need every vertex at least this far (a fraction of the distance to the
/// light plane) from the receiver's plane: their uv then stay within ~1/kOpenMinW of the square.
constexpr double kOpenMinW = 1e-3;

/// The unrounded light uv × kUvScale of a homogeneous point with W > 0.
DVec2 open_uv(const DVec3& h) {
  return DVec2(h.x / h.z * kUvScale, h.y / h.z * kUvScale);
}

/// Rec. 709 luminance, the collapse of a textured light's RGB visibility to one V_coef that the
/// sampling methods use too (light_weights.hpp).
double luminance(const DVec3& rgb) {
  return 0.2126 * rgb.x + 0.7152 * rgb.y + 0.0722 * rgb.z;
}

/// Does the segment origin + t·dir, t ∈ (0, 1], cross the triangle (a, b, c)? Möller–Trumbore in
/// double, edges inclusive. A segment lying in the triangle's plane crosses it in a set of
/// measure zero and is not counted.
bool segment_hits_triangle(const DVec3& origin, const DVec3& dir, const DVec3& a, const DVec3& b,
                           const DVec3& c) {
  const DVec3 e1 = b - a, e2 = c - a;
  const DVec3 pvec = glm::cross(dir, e2);
  const double det = glm::dot(e1, pvec);
  if (det == 0.0 || !std::isfinite(det)) return false;
  const double inv = 1.0 / det;
  const DVec3 tvec = origin - a;
  const double u = glm::dot(tvec, pvec) * inv;
  if (u < 0.0 || u > 1.0) return false;
  const DVec3 qvec = glm::cross(tvec, e1);
  const double v = glm::dot(dir, qvec) * inv;
  if (v < 0.0 || u + v > 1.0) return false;
  const double t = glm::dot(e2, qvec) * inv;
  return t > 0.0 && t <= 1.0;
}

/// Does the convex light-uv polygon cover the whole uv square? (Then the receiver is in umbra.)
bool covers_square(const ClipperLib::Path& poly) {
  const ClipperLib::cInt s = static_cast<ClipperLib::cInt>(kUvScale);
  const ClipperLib::IntPoint corners[4] = {{0, 0}, {s, 0}, {s, s}, {0, s}};
  for (const ClipperLib::IntPoint& c : corners)
    if (ClipperLib::PointInPolygon(c, poly) == 0) return false;  // −1 (on the boundary) counts
  return true;
}

// Back-face culling, exactly. Let S be an ExactSolid: an opaque mesh M plus caps C such that
// Z = M + C is a 2-cycle (no boundary). Z gives space off it an integer winding number w (0 far
// away), and a segment crossing a triangle T of Z transversally changes w by +1 when it goes from
// the side T's normal n_T = (v1 − v0) × (v2 − v0) points to onto the other (it "enters"), by −1
// otherwise. From the receiver p, the triangles it sees from their positive side
// (n_T·(p − v0) > 0) can only be entered by segments leaving p, those it sees from behind only
// left.
//
// Claim: if w(q) = 0 at every light point q, no segment from p to the light meets a cap, and
// w(p) ≤ 0, the light points blocked by M (segment p → q meets M) are, up to a set of measure zero,
// those blocked by the triangles of M seen from their positive side; if w(p) ≥ 0, those seen from
// behind.
// Proof: drop the measure-zero set of q whose segment passes through an edge or vertex of Z or
// lies in a triangle's plane; every other segment crosses Z transversally at finitely many points,
// all on M (it misses the caps). Along p → q, w goes from w(p) to w(q) = 0 in steps of ±1. If the
// segment crosses M but never enters, all its k ≥ 1 steps are −1 and 0 = w(p) − k, so w(p) ≥ 1:
// impossible when w(p) ≤ 0. Hence every blocked q is blocked by an entered triangle, which p sees
// from its positive side. Symmetrically for w(p) ≥ 0 with the −1 steps. The skipped triangles'
// projections thus lie inside the kept ones' union up to measure zero, and the visible area V is
// unchanged. Self-intersections, inward orientation, holes and inconsistent neighbours need no
// special case: the caps make Z a cycle whatever M is. ∎
// The premises are checked conservatively per pixel: the light's parallelogram outside S's box
// (so w(q) = 0), the pyramid from p to the light missing every cap's box (every segment p → q lies
// in the pyramid), and w(p) = 0 outside S's box or else counted along a ray (winding_number);
// any doubt (a crossing within 1e-9 of an edge, a ray nearly in a triangle's plane) keeps every
// triangle of S. One caveat outside the proof: project_polygon ignores what lies within kMinW
// (1e-9 of the distance to the light) of p, culled or not; only a surface passing that close to p
// — a thousand times closer than the shared ray offset — could make the two differ.
enum class Cull : uint8_t { all, keep_positive, keep_negative, unknown };

bool boxes_overlap(const Bounds3& a, const Bounds3& b) {
  for (int i = 0; i < 3; ++i) {
    const double pad =
        1e-9 * (std::abs(a.lo[i]) + std::abs(a.hi[i]) + std::abs(b.lo[i]) + std::abs(b.hi[i]));
    if (a.hi[i] + pad < b.lo[i] || b.hi[i] + pad < a.lo[i]) return false;
  }
  return true;
}

/// Which triangles of solid `s` the receiver p may skip for the light parallelogram `light_box`.
Cull cull_mode(const ExactScene& scene, uint32_t s, const DVec3& p, const Bounds3& light_box,
               const LightProjection& proj) {
  const ExactSolid& solid = scene.solids()[s];
  const Bounds3& box = solid.box;
  if (boxes_overlap(box, light_box)) return Cull::all;  // w(q) = 0 not established
  for (const Bounds3& cap : solid.cap_boxes)
    if (box_meets_pyramid(proj, cap.lo, cap.hi)) return Cull::all;  // a segment may cross a cap
  Bounds3 point;
  point.extend(Vec3(p));
  if (!boxes_overlap(box, point)) return Cull::keep_positive;  // outside the box: w(p) = 0
  int w = 0;
  if (!winding_number(scene, s, p, w)) return Cull::all;
  return w <= 0 ? Cull::keep_positive : Cull::keep_negative;
}

ExactPointResult point_light_visibility(const ExactScene& scene, const DVec3& p,
                                        const DVec3& light_pos) {
  ExactPointResult r;
  const DVec3 dir = light_pos - p;
  const auto& occluders = scene.occluders();
  double v = 1.0;
  scene.bvh().traverse(
      [&](const ExactBvh::Node& n) { return segment_meets_box(p, dir, n.lo, n.hi); },
      [&](uint32_t prim) {
        ++r.candidates;
        const ExactOccluder& o = occluders[prim];
        bool hit = false;
        if (!o.cut) {
          hit = segment_hits_triangle(p, dir, o.v[0], o.v[1], o.v[2]);
        } else {
          // The alpha mask decides through the same opaque pieces the area case projects. Pieces
          // of one triangle do not overlap: one crossing at most, even on a shared edge.
          for (uint32_t k = o.piece_first; k < o.piece_first + o.piece_count && !hit; ++k) {
            const ExactPiece& piece = scene.pieces()[k];
            const DVec3* pv = scene.piece_vertices().data() + piece.first;
            for (uint32_t j = 1; j + 1 < piece.count && !hit; ++j)
              hit = segment_hits_triangle(p, dir, pv[0], pv[j], pv[j + 1]);
          }
        }
        if (hit) {
          ++r.polygons;
          v *= o.transmittance;
        }
        return v > 0.0;
      });
  r.visible = v;
  r.visible_rgb = DVec3(v);
  return r;
}

/// Carried over the receivers a thread visits: the kept-triangle marks (by epoch, so no pixel
/// clears them) and the per-pixel lists, allocated once.
struct Scratch {
  struct OpenTriangle {
    OpenTriangle() {}  // filled where it is listed (keep_opaque): not zeroed first
    uint32_t prim;
    DVec2 q[3];  // uv × kUvScale of v[0], v[1], v[2]
  };
  std::vector<uint32_t> stamp;  // (epoch << 2) | open << 1 | positive side, kept triangles
  uint32_t epoch = 0;
  std::vector<uint32_t> inside;    // kept triangles from boxes inside the pyramid (not clipped)
  std::vector<OpenTriangle> open;  // kept triangles straddling the sides, projected whole
  std::vector<uint32_t> tri;       // kept triangles clipped during the traversal
  std::vector<ClippedPolygon> clipped;  // their projections, tri[i] → clipped[i]
  std::vector<DirectedEdge> edges;
  std::vector<UvEdge> uv;
  std::vector<uint32_t> edge_prim, uv_prim;  // the triangle each of edges, uv comes from
  std::vector<uint64_t> union_find;  // per triangle: epoch << 32 | parent, kept ones (groups)
  std::vector<Cull> cull;            // per solid, decided at its first candidate
  std::vector<uint8_t> solid_met;
  std::vector<uint8_t> edge_path;  // per solid: its silhouette comes from its edge tree
  std::vector<SemiPolygon> semi;
  ClipperLib::Paths loops;
  ClipperLib::Path poly;
};

// Opaque uncut triangles are not projected whole and then cancelled edge by edge: the edge
// between two kept triangles of one mesh whose projections have the same orientation appears in
// both, in opposite directions and bit-identical after clipping (clip_polygon), so the pair is
// known to cancel from adjacency alone and neither copy is emitted. What is left is the
// projected silhouette of the kept set (for a closed mesh, its light-facing part), plus the
// pieces along the pyramid's faces, with the same winding-number field as the sum of the
// polygons. A triangle whose box lies strictly inside the pyramid (no clipping) and whose three
// neighbours are all kept with its orientation contributes nothing and is never projected.
// Every kept triangle is marked in `stamp` with the pixel's epoch, its side and how it was
// projected, so both triangles of a shared edge take the same decision.
//
// Where V is the area of the uniformly emitting square left uncovered (rectangular untextured
// light, no semi-opaque occluder: `open_ok`), the area sweep measures the winding field inside
// the square whatever the edges do outside it, so a triangle straddling the pyramid's sides
// need not be clipped there: it is projected whole ("open": unrounded uv of its three vertices)
// when all of them lie between p and the light, W in [kOpenMinW, kShadowSegmentEnd] (W bounded
// away from 0 keeps the coordinates, and their rounding, small). Triangles inside the pyramid
// are open too (clipping would not change them); the others are clipped as before. A shared
// edge cancels only between two triangles projected the same way (their copies are then
// identical); across the two ways both copies are emitted, and their sum is still the sum of
// the two polygons' fields.
class PixelUnion {
 public:
  /// `edge_trees`: large solids may give their silhouette from their edge trees.
  PixelUnion(const ExactScene& scene, const ExactLight& light, const DVec3& p,
             const LightFrame& frame, const LightProjection& proj, ExactPointResult& r,
             bool edge_trees)
      : scene_(scene), light_(light), p_(p), frame_(frame), proj_(proj), r_(r), sc_(scratch()) {
    for (const Vec3& c : {frame.corner, frame.corner + frame.edge_u, frame.corner + frame.edge_v,
                          frame.corner + frame.edge_u + frame.edge_v})
      light_box_.extend(c);
    sc_.cull.assign(scene.solids().size(), Cull::unknown);
    if (sc_.stamp.size() < scene.occluders().size()) sc_.stamp.resize(scene.occluders().size(), 0);
    if (++sc_.epoch >= (1u << 30)) {  // epochs only grow: stamps of earlier pixels never match
      std::fill(sc_.stamp.begin(), sc_.stamp.end(), 0u);
      std::fill(sc_.union_find.begin(), sc_.union_find.end(), 0u);
      sc_.epoch = 1;
    }
    mark_ = sc_.epoch << 2;
    open_ok_ = !light.outline().round && !light.textured() && !scene.semi_opaque();
    open_bit_ = open_ok_ ? 2u : 0u;
    det_positive_ = glm::dot(proj.to_u, glm::cross(proj.to_v, proj.to_w)) > 0.0;
    sc_.inside.clear();
    sc_.open.clear();
    sc_.tri.clear();
    sc_.edges.clear();
    sc_.edge_prim.clear();
    sc_.semi.clear();
    if (edge_trees && open_ok_ && !scene.edge_tree_solids().empty()) choose_edge_paths();
  }

  /// In umbra by the solids' inner balls (solid_interior.hpp) of `solid_met` (empty: all)?
  /// Records the answer in `hint` and, when hidden, in the result.
  bool balls_hide_light(std::span<const uint8_t> solid_met, ExactUmbraHint* hint) {
    const bool hidden =
        inner_balls_hide_light(scene_, p_, DVec3(frame_.corner), DVec3(frame_.edge_u),
                               DVec3(frame_.edge_v), light_box_, proj_, solid_met);
    if (hint != nullptr) hint->previous_umbra = hidden;
    if (hidden) {
      r_.visible = 0.0;
      r_.visible_rgb = DVec3(0.0);
      r_.umbra_by_ball = true;
    }
    return hidden;
  }

  /// Finds and marks the triangles that may change the union; false when one opaque polygon
  /// covers the whole light (then V = 0 is set).
  bool collect() {
    scene_.bvh().traverse_classified(
        [&](const ExactBvh::Node& n, bool inside) { return classify_node(n, inside); },
        [&](uint32_t prim, bool inside) { return visit(prim, inside); });
    if (umbra_) {
      r_.visible = 0.0;
      r_.visible_rgb = DVec3(0.0);
    }
    return !umbra_;
  }

  /// Was anything kept? (Otherwise nothing blocks the light.)
  bool met_something() const {
    return !sc_.inside.empty() || !sc_.open.empty() || clipped_count_ > 0 || !sc_.edges.empty() ||
           !sc_.semi.empty() || !edge_solids_.empty();
  }

  /// After emit_silhouette: the silhouettes of the solids that take the edge path appended;
  /// false when one of them is unsure (edge_tree.hpp), then the receiver is done again without
  /// edge trees. `any` becomes true when some edge was appended.
  bool append_edge_silhouettes(bool& any);

  /// The solids whose cull mode the traversal decided, i.e. which it met.
  std::span<const uint8_t> solids_met() {
    sc_.solid_met.resize(sc_.cull.size());
    for (size_t s = 0; s < sc_.cull.size(); ++s)
      sc_.solid_met[s] = sc_.cull[s] != Cull::unknown ? 1 : 0;
    return sc_.solid_met;
  }

  /// The kept triangles' edges that do not cancel: clipped ones into sc_.edges, open ones into
  /// sc_.uv; false when there are none and no semi-opaque polygon either.
  bool emit_silhouette();

  /// V (and its RGB) from the emitted edges.
  void measure() {
    if (open_ok_) {
      measure_by_sweep();
    } else {
      measure_by_clipper();
    }
  }

 private:
  static Scratch& scratch() {
    thread_local Scratch sc;
    return sc;
  }
  Cull& cull_of(uint32_t solid) {
    Cull& mode = sc_.cull[solid];
    if (mode == Cull::unknown) mode = cull_mode(scene_, solid, p_, light_box_, proj_);
    return mode;
  }
  /// `side` = normal · (p − v0): positive where p sees the triangle's positive side.
  bool skipped(const ExactOccluder& o, double side) {
    if (o.solid == ExactOccluder::kNotSolid) return false;
    const Cull mode = cull_of(o.solid);
    if (mode == Cull::all) return false;
    return mode == Cull::keep_positive ? !(side > 0.0) : !(side < 0.0);
  }
  int classify_node(const ExactBvh::Node& n, bool inside);
  bool visit(uint32_t prim, bool inside);
  void choose_edge_paths();
  void add_piece(const ExactOccluder& o, const DVec3* vertices, int count);
  bool keep_opaque(uint32_t prim, const ExactOccluder& o, double side, bool inside);
  void emit_clipped(uint32_t prim, const ClippedPolygon& c);
  void emit_open(uint32_t prim, const DVec2* q);
  void label_cancellation_groups(std::vector<uint32_t>& prim_of_edge);
  void measure_by_sweep();
  void measure_by_clipper();

  const ExactScene& scene_;
  const ExactLight& light_;
  const DVec3 p_;
  const LightFrame& frame_;
  const LightProjection& proj_;
  ExactPointResult& r_;
  Scratch& sc_;
  Bounds3 light_box_;
  uint32_t mark_ = 0;
  bool open_ok_ = false;
  uint32_t open_bit_ = 0;
  bool det_positive_ = false;  // emit_clipped: det M > 0
  size_t clipped_count_ = 0;
  std::vector<uint32_t> edge_solids_;  // the solids marked in sc_.edge_path
  uint32_t pieces_ = 0;                // non-degenerate opaque alpha pieces
  bool umbra_ = false;
};

int PixelUnion::classify_node(const ExactBvh::Node& n, bool inside) {
  const auto& occluders = scene_.occluders();
  const std::vector<ExactNodeCone>& cones = scene_.node_cones();
  const std::vector<ExactBvh::Node>& nodes = scene_.bvh().nodes();
  // A leaf's occluders are slots [first, first + count) (leaf order): their records are
  // fetched while its box is classified, the first thing their visit reads.
  if (n.count > 0) {
    const char* record = reinterpret_cast<const char*>(&occluders[n.first]);
    const char* last = reinterpret_cast<const char*>(&occluders[n.first + n.count - 1]);
    for (; record <= last; record += 64) __builtin_prefetch(record);
  }
  // Inside the pyramid the box test is skipped, the back-face test is not: a subtree
  // holding a whole solid seen from outside has both sides, its children often one.
  const size_t index = static_cast<size_t>(&n - nodes.data());
  // The cones are read after the box test: fetched meanwhile.
  const auto fetch_cone = [&](size_t k) { __builtin_prefetch(&cones[k]); };
  if (!cones.empty()) fetch_cone(index);
  const int c = inside ? ExactBvh::kInside : classify_box(proj_, n.lo, n.hi);
  if (c == ExactBvh::kOutside || cones.empty()) return c;
  if (n.count == 0) {  // descending: both children's cones
    fetch_cone(index + 1);
    fetch_cone(n.first);
  }
  const ExactNodeCone& cone = cones[index];
  if (cone.solid == ExactOccluder::kNotSolid) return c;
  if (!edge_solids_.empty() && sc_.edge_path[cone.solid]) return ExactBvh::kOutside;
  const Cull mode = cull_of(cone.solid);
  if (mode == Cull::all || !subtree_culled(cone, n, p_, mode == Cull::keep_positive)) return c;
  r_.candidates += cone.triangles;
  r_.culled += cone.triangles;
  return ExactBvh::kOutside;
}

/// Which met solids give their silhouette from their edge trees: those p sees from outside
/// (a cull mode keeping one side) that lie wholly nearer than the light's end of the segment —
/// no kept face crosses the pyramid's far face, so the silhouette edges and the count along the
/// left side fix the field (edge_tree.hpp).
void PixelUnion::choose_edge_paths() {
  sc_.edge_path.assign(scene_.solids().size(), 0);
  for (const uint32_t s : scene_.edge_tree_solids()) {
    const Bounds3& box = scene_.solids()[s].box;
    if (classify_box(proj_, box.lo, box.hi) == ExactBvh::kOutside) continue;
    const Cull mode = cull_of(s);
    if (mode != Cull::keep_positive && mode != Cull::keep_negative) continue;
    double far_w = 0.0;  // W is linear: its largest value over the box, corner by corner
    for (int i = 0; i < 3; ++i) {
      const double lo = proj_.to_w[i] * (box.lo[i] - proj_.origin[i]);
      const double hi = proj_.to_w[i] * (box.hi[i] - proj_.origin[i]);
      far_w += std::max(lo, hi);
    }
    if (!(far_w < kShadowSegmentEnd * (1.0 - 1e-9))) continue;
    sc_.edge_path[s] = 1;
    edge_solids_.push_back(s);
  }
}

bool PixelUnion::append_edge_silhouettes(bool& any) {
  for (const uint32_t s : edge_solids_) {
    EdgeSilhouetteQuery q;
    q.scene = &scene_;
    q.solid = s;
    q.p = p_;
    q.proj = &proj_;
    q.corner = DVec3(frame_.corner);
    q.edge_v = DVec3(frame_.edge_v);
    q.keep_positive = sc_.cull[s] == Cull::keep_positive;
    q.det_positive = det_positive_;
    q.label = static_cast<uint32_t>(scene_.occluders().size()) + s;
    const size_t before = sc_.uv.size();
    if (!append_edge_silhouette(q, sc_.uv, sc_.uv_prim, r_.edge_tree_edges)) return false;
    ++r_.edge_tree_solids;
    any = any || sc_.uv.size() > before;
  }
  return true;
}

/// An alpha piece or a semi-opaque triangle: clipped and projected now, its outline added to
/// the edges (opaque) or kept for the weighted regions (semi-opaque).
void PixelUnion::add_piece(const ExactOccluder& o, const DVec3* vertices, int count) {
  ClipperLib::Path& poly = sc_.poly;
  if (!project_polygon(proj_, vertices, count, poly)) return;
  ++r_.polygons;
  if (o.transmittance > 0.0) {
    sc_.semi.push_back({poly, o.transmittance});
    return;
  }
  ++pieces_;
  append_polygon_edges(std::span<const ClipperLib::Path>(&poly, 1), sc_.edges);
  // One group per cut triangle for the divided sweep (its pieces do not overlap), labelled past
  // the triangles and the edge trees' solids so that the grouping leaves it alone.
  const uint32_t label = static_cast<uint32_t>(scene_.occluders().size() + scene_.solids().size() +
                                               static_cast<size_t>(&o - scene_.occluders().data()));
  sc_.edge_prim.resize(sc_.edges.size(), label);
  umbra_ = umbra_ || covers_square(poly);
}

/// One candidate triangle (`inside`: its leaf's box lies inside the pyramid); false stops the
/// traversal (the light is covered).
bool PixelUnion::visit(uint32_t prim, bool inside) {
  const ExactOccluder& o = scene_.occluders()[prim];
  if (!edge_solids_.empty() && o.solid != ExactOccluder::kNotSolid && sc_.edge_path[o.solid])
    return true;  // its silhouette comes from its edge tree
  ++r_.candidates;
  const double side = glm::dot(o.normal, p_ - o.v[0]);
  if (skipped(o, side)) {
    ++r_.culled;
    return true;
  }
  if (o.cut) {
    for (uint32_t k = o.piece_first; k < o.piece_first + o.piece_count; ++k) {
      const ExactPiece& piece = scene_.pieces()[k];
      add_piece(o, scene_.piece_vertices().data() + piece.first, static_cast<int>(piece.count));
    }
    return !umbra_;
  }
  if (o.transmittance > 0.0) {
    add_piece(o, o.v, 3);
    return true;
  }
  if (side == 0.0) return true;  // seen edge-on: projects onto a segment (measure zero)
  return keep_opaque(prim, o, side, inside);
}

/// An opaque uncut triangle p sees from `side`: marked, and listed as inside, open or clipped.
bool PixelUnion::keep_opaque(uint32_t prim, const ExactOccluder& o, double side, bool inside) {
  constexpr cInt kSide = static_cast<cInt>(kUvScale);
  DVec3 h[3];
  if (!inside) {
    // The leaf straddles the pyramid; the triangle itself often does not: its vertices
    // against the clip's own half-spaces, from the values the clip would test.
    for (int k = 0; k < 3; ++k) h[k] = proj_.homogeneous(o.v[k]);
    const int own = classify_homogeneous(h, 3);
    if (own == ExactBvh::kOutside) return true;  // projects to nothing
    inside = own == ExactBvh::kInside;
  }
  const uint32_t side_bit = side > 0.0 ? 1u : 0u;
  if (inside) {
    sc_.stamp[prim] = mark_ | open_bit_ | side_bit;
    sc_.inside.push_back(prim);
    ++r_.polygons;
    return true;
  }
  if (open_ok_ && h[0].z >= kOpenMinW && h[1].z >= kOpenMinW && h[2].z >= kOpenMinW &&
      h[0].z <= kShadowSegmentEnd && h[1].z <= kShadowSegmentEnd && h[2].z <= kShadowSegmentEnd) {
    // Built in place (a temporary's zeroing and copy were string instructions here).
    Scratch::OpenTriangle& t = sc_.open.emplace_back();
    t.prim = prim;
    for (int k = 0; k < 3; ++k) t.q[k] = open_uv(h[k]);
    // One that may cover the whole square is clipped instead (the umbra test below).
    const double lo_x = std::min({t.q[0].x, t.q[1].x, t.q[2].x});
    const double hi_x = std::max({t.q[0].x, t.q[1].x, t.q[2].x});
    const double lo_y = std::min({t.q[0].y, t.q[1].y, t.q[2].y});
    const double hi_y = std::max({t.q[0].y, t.q[1].y, t.q[2].y});
    if (!(lo_x <= 0.0 && lo_y <= 0.0 && hi_x >= kUvScale && hi_y >= kUvScale)) {
      sc_.stamp[prim] = mark_ | open_bit_ | side_bit;
      ++r_.polygons;
      return true;
    }
    sc_.open.pop_back();
  }
  sc_.stamp[prim] = mark_ | side_bit;
  if (sc_.clipped.size() == clipped_count_) sc_.clipped.emplace_back();
  ClippedPolygon& c = sc_.clipped[clipped_count_];
  clip_homogeneous(h, 3, c);
  if (c.n == 0) return true;
  ++clipped_count_;
  sc_.tri.push_back(prim);
  if (c.n >= 3) ++r_.polygons;
  if (c.n >= 4) {
    // Only a polygon reaching all four sides of the uv square can cover it.
    cInt lo_x = kSide, hi_x = 0, lo_y = kSide, hi_y = 0;
    for (int i = 0; i < c.n; ++i) {
      lo_x = std::min(lo_x, c.q[i].X);
      hi_x = std::max(hi_x, c.q[i].X);
      lo_y = std::min(lo_y, c.q[i].Y);
      hi_y = std::max(hi_y, c.q[i].Y);
    }
    if (lo_x == 0 && lo_y == 0 && hi_x == kSide && hi_y == kSide) {
      sc_.poly.assign(c.q, c.q + c.n);
      umbra_ = covers_square(sc_.poly);
    }
  }
  return !umbra_;  // one opaque polygon hides the whole light: done
}

// The projection's orientation: with M the rows to_u, to_v, to_w, det[h0 h1 h2] =
// det M · det[x0 − p, x1 − p, x2 − p] = −det M · side, and W > 0 after clipping, so a polygon
// keeps its vertex order's orientation in uv iff det M · side < 0. Every polygon enters the
// union positively oriented (see project_polygon).
void PixelUnion::emit_clipped(uint32_t prim, const ClippedPolygon& c) {
  const std::array<uint32_t, 3>& neighbour = scene_.neighbours()[prim];
  const uint32_t own = sc_.stamp[prim];
  const bool flip = det_positive_ == ((own & 1u) != 0);
  for (int i = 0; i < c.n; ++i) {
    const int e = c.edge[i];
    if (e >= 0) {
      const uint32_t nb = neighbour[e];
      if (nb != ExactOccluder::kNoNeighbour && sc_.stamp[nb] == own) continue;  // cancels
    }
    const ClipperLib::IntPoint& a = c.q[i];
    const ClipperLib::IntPoint& b = c.q[i + 1 == c.n ? 0 : i + 1];
    if (a == b) continue;
    sc_.edges.push_back(flip ? DirectedEdge{b, a} : DirectedEdge{a, b});
    sc_.edge_prim.push_back(prim);
  }
}

void PixelUnion::emit_open(uint32_t prim, const DVec2* q) {
  const std::array<uint32_t, 3>& neighbour = scene_.neighbours()[prim];
  const uint32_t own = sc_.stamp[prim];
  const bool flip = det_positive_ == ((own & 1u) != 0);
  for (int e = 0; e < 3; ++e) {
    const uint32_t nb = neighbour[e];
    if (nb != ExactOccluder::kNoNeighbour && sc_.stamp[nb] == own) continue;  // cancels
    const DVec2& a = q[e];
    const DVec2& b = q[e == 2 ? 0 : e + 1];
    sc_.uv.push_back(flip ? UvEdge{b.x, b.y, a.x, a.y} : UvEdge{a.x, a.y, b.x, b.y});
    sc_.uv_prim.push_back(prim);
  }
}

bool PixelUnion::emit_silhouette() {
  for (size_t i = 0; i < clipped_count_; ++i) emit_clipped(sc_.tri[i], sc_.clipped[i]);
  sc_.uv.clear();
  sc_.uv_prim.clear();
  for (const Scratch::OpenTriangle& t : sc_.open) emit_open(t.prim, t.q);
  ClippedPolygon unclipped;
  const auto& neighbours = scene_.neighbours();
  for (const uint32_t prim : sc_.inside) {
    const uint32_t own = sc_.stamp[prim];
    bool interior = true;
    for (const uint32_t nb : neighbours[prim])
      interior = interior && nb != ExactOccluder::kNoNeighbour && sc_.stamp[nb] == own;
    if (interior) continue;
    const ExactOccluder& o = scene_.occluders()[prim];
    if (open_ok_) {
      DVec2 q[3];
      for (int k = 0; k < 3; ++k) q[k] = open_uv(proj_.homogeneous(o.v[k]));
      emit_open(prim, q);
      continue;
    }
    clip_polygon(proj_, o.v, 3, unclipped);
    emit_clipped(prim, unclipped);
  }
  return !sc_.edges.empty() || !sc_.uv.empty() || !sc_.semi.empty();
}

// Many edges: the sweep divides them into groups whose winding field is ≥ 0 on its own — the
// kept triangles joined by cancelled shared edges (same stamp), each such set's emitted edges
// the outline of the sum of its positively oriented polygons. Replaces each edge's triangle
// by its set's label.
void PixelUnion::label_cancellation_groups(std::vector<uint32_t>& prim_of_edge) {
  // Union-find indexed by triangle, each entry tagged with the pixel's epoch: the sweep reads
  // only which edges share a label (the partition), and the tag says at once whether a
  // neighbour is listed, without a second lookup through a local index.
  const uint64_t tag = static_cast<uint64_t>(sc_.epoch) << 32;
  const auto& neighbours = scene_.neighbours();
  std::vector<uint64_t>& uf = sc_.union_find;
  if (uf.size() < scene_.occluders().size()) uf.resize(scene_.occluders().size(), 0);
  for (size_t i = 0; i < clipped_count_; ++i) uf[sc_.tri[i]] = tag | sc_.tri[i];
  for (const Scratch::OpenTriangle& t : sc_.open) uf[t.prim] = tag | t.prim;
  for (const uint32_t prim : sc_.inside) uf[prim] = tag | prim;
  const auto find = [&](uint32_t i) {
    for (;;) {
      const uint32_t up = static_cast<uint32_t>(uf[i]);
      if (up == i) return i;
      const uint32_t upper = static_cast<uint32_t>(uf[up]);
      uf[i] = tag | upper;
      i = upper;
    }
  };
  // (A triangle stamped but clipped to nothing is in no list and joins nothing: it emitted
  // nothing, and an edge it cancelled was clipped away in its neighbour too.)
  // Each shared edge once, from its triangle with the larger index (kNoNeighbour is larger
  // than any): both triangles are listed or the edge joins nothing either way.
  const auto join = [&](uint32_t prim) {
    const uint32_t own = sc_.stamp[prim];
    for (const uint32_t nb : neighbours[prim])
      if (nb < prim && sc_.stamp[nb] == own && (uf[nb] & ~0xffffffffull) == tag)
        uf[find(prim)] = tag | find(nb);
  };
  for (size_t i = 0; i < clipped_count_; ++i) join(sc_.tri[i]);
  for (const Scratch::OpenTriangle& t : sc_.open) join(t.prim);
  for (const uint32_t prim : sc_.inside) join(prim);
  // Labels past the triangles are edge trees' (one group per solid, edge_tree.hpp) and cut
  // triangles' (one group each).
  const size_t triangles = scene_.occluders().size();
  for (uint32_t& e : prim_of_edge)
    if (e < triangles) e = find(e);
}

/// The whole uv square emits uniformly and every polygon is opaque: V is the area where the
/// edges' winding number is 0, swept from the edges directly (no loops, no boolean).
void PixelUnion::measure_by_sweep() {
  append_uv_edges(sc_.edges, sc_.uv);
  r_.silhouette_edges = static_cast<uint32_t>(sc_.uv.size());
  double area = 0.0;
  SweepWork work;
  if (sc_.uv.size() <= kDivideAboveEdges) {
    area = uncovered_square_area(sc_.uv, &work);
  } else {
    sc_.uv_prim.insert(sc_.uv_prim.end(), sc_.edge_prim.begin(), sc_.edge_prim.end());
    label_cancellation_groups(sc_.uv_prim);
    area = uncovered_square_area(sc_.uv, sc_.uv_prim, &work);
  }
  r_.sweep_edge_beams = work.edge_beams;
  r_.sweep_beams = work.beams;
  r_.sweep_crossings = work.crossings;
  const double v = area / light_.outline().area;
  r_.visible = std::isfinite(v) ? std::clamp(v, 0.0, 1.0) : 1.0;
  r_.visible_rgb = DVec3(r_.visible);
}

/// Round or textured lights, semi-opaque occluders: loops traced from the edges, the light minus
/// their union (and the semi-opaque regions, weighted) by Clipper; textured lights weight it by
/// texel per channel.
void PixelUnion::measure_by_clipper() {
  // Mesh edges were cancelled from adjacency; only alpha pieces (and their shared edges) need
  // the hash.
  const size_t loop_count = trace_loops(sc_.edges, sc_.loops, pieces_ > 0);
  const std::span<const ClipperLib::Path> loops(sc_.loops.data(), loop_count);
  const std::vector<LightRegion> regions = visible_regions(light_.outline(), loops, sc_.semi);
  double visible_area = 0.0;
  for (const LightRegion& region : regions)
    visible_area += region.weight * paths_area(region.paths);
  double v = visible_area / light_.outline().area;
  v = std::isfinite(v) ? std::clamp(v, 0.0, 1.0) : 1.0;
  r_.visible = v;
  r_.visible_rgb = DVec3(v);
  if (!light_.textured()) return;
  // Per channel Σ_texels weight · area(texel ∩ visible) / Σ_texels weight · area(texel ∩ light).
  DVec3 seen(0.0);
  for (const LightRegion& region : regions)
    seen += region.weight * texel_weighted_area(region.paths, light_.texture_width(),
                                                light_.texture_height(), light_.texel_weight());
  const DVec3& total = light_.total_weight();
  for (int c = 0; c < 3; ++c) {
    const double f = total[c] > 0.0 ? seen[c] / total[c] : 1.0;
    r_.visible_rgb[c] = std::isfinite(f) ? std::clamp(f, 0.0, 1.0) : 1.0;
  }
  const double lum_total = luminance(total);
  const double f = lum_total > 0.0 ? luminance(seen) / lum_total : 1.0;
  r_.visible = std::isfinite(f) ? std::clamp(f, 0.0, 1.0) : 1.0;
}

}  // namespace

ExactPointResult exact_visibility(const ExactScene& scene, const ExactLight& light,
                                  const Vec3& receiver, ExactUmbraHint* hint) {
  ExactPointResult r;
  const DVec3 p(receiver);
  if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) {
    r.degenerate = true;
    return r;
  }
  const LightFrame frame = light_frame(light.light(), receiver);
  if (light.light().shape == LightShape::point)
    return point_light_visibility(scene, p, DVec3(frame.corner));

  LightProjection proj;
  if (!make_light_projection(p, DVec3(frame.corner), DVec3(frame.edge_u), DVec3(frame.edge_v),
                             proj)) {
    // The receiver lies in the light's plane: every occluder projects onto a line, the visible
    // fraction is undefined. Documented fallback ("light touching geometry"): fully lit.
    r.degenerate = true;
    return r;
  }
  // In umbra by the solids' inner balls? Tried before the traversal where the previous receiver
  // was (neighbours mostly share their umbra), else after it where something was met.
  const bool hinted = hint != nullptr && hint->previous_umbra;
  {
    PixelUnion query(scene, light, p, frame, proj, r, true);
    if (hinted && query.balls_hide_light({}, hint)) return r;
    if (!query.collect()) return r;
    if (query.met_something() && !hinted && query.balls_hide_light(query.solids_met(), hint))
      return r;
    bool any = query.emit_silhouette();
    if (query.append_edge_silhouettes(any)) {
      if (any) query.measure();
      return r;
    }
  }
  // An edge tree was unsure: the same receiver by its faces alone.
  r = ExactPointResult{};
  r.edge_tree_fallbacks = 1;
  PixelUnion faces(scene, light, p, frame, proj, r, false);
  if (!faces.collect()) return r;
  if (faces.emit_silhouette()) faces.measure();
  return r;
}

double exact_visible_fraction(const ExactScene& scene, const Light& light, Vec3 receiver,
                              int disk_segments) {
  const ExactLight exact_light(scene.scene(), light, disk_segments);
  return exact_visibility(scene, exact_light, receiver).visible;
}

namespace {

class ExactMethod final : public ShadowMethod {
 public:
  explicit ExactMethod(const ExactOptions& options) : options_(options) {}

  /// The occluders, their BVH and the closed solids' inner balls depend on the meshes alone.
  void prepare(const Scene& scene) override {
    const auto start = std::chrono::steady_clock::now();
    prepared_ = std::make_unique<const ExactScene>(scene, options_.leaf_size,
                                                   options_.cull_back_faces, options_.edge_trees);
    unreported_prepare_ms_ = elapsed_ms(start);
  }

  Visibility compute(const ShadowContext& ctx) override {
    const GBuffer& g = ctx.gbuffer;
    Visibility vis;
    vis.lit = Image<float>(g.width, g.height, 1.0f);

    if (!prepared_) prepare(ctx.scene);  // a caller that skipped prepare()
    const auto light_start = std::chrono::steady_clock::now();
    const ExactScene& scene = *prepared_;
    const ExactLight light(ctx.scene, ctx.light, options_.disk_segments);
    // Stage "bvh": the light's polygon, plus the preparation for the first light after it.
    vis.times.add("bvh", unreported_prepare_ms_ + elapsed_ms(light_start));
    unreported_prepare_ms_ = 0.0;
    if (light.textured()) vis.lit_rgb = Image<Vec3>(g.width, g.height, Vec3(1.0f));

    // Per-row statistics, summed in row order afterwards: the counters never depend on threads.
    struct RowStats {
      double pixels = 0, candidates = 0, candidates_max = 0, polygons = 0, culled = 0;
      double lit = 0, umbra = 0, penumbra = 0, degenerate = 0, umbra_by_ball = 0;
      double sweep_edge_beams = 0, sweep_beams = 0, sweep_crossings = 0, silhouette_edges = 0;
      double edge_tree_solids = 0, edge_tree_edges = 0, edge_tree_fallbacks = 0;
    };
    std::vector<RowStats> rows(static_cast<size_t>(std::max(0, g.height)));
    {
      ScopedStage stage(vis.times, "visibility");
      Progress progress("exact", static_cast<size_t>(g.height));
      parallel_rows(g.height, [&](int y) {
        RowStats& s = rows[static_cast<size_t>(y)];
        ExactUmbraHint hint;  // per row: the counters never depend on threads
        for (int x = 0; x < g.width; ++x) {
          const size_t i = static_cast<size_t>(y) * g.width + x;
          if (ctx.receivers[i] != kActive) continue;
          const ExactPointResult r = exact_visibility(scene, light, g.shadow_origin(i), &hint);
          vis.lit[i] = static_cast<float>(r.visible);
          if (vis.lit_rgb) (*vis.lit_rgb)[i] = Vec3(r.visible_rgb);
          s.pixels += 1;
          s.candidates += r.candidates;
          s.candidates_max = std::max(s.candidates_max, static_cast<double>(r.candidates));
          s.polygons += r.polygons;
          s.culled += r.culled;
          s.degenerate += r.degenerate ? 1 : 0;
          s.umbra_by_ball += r.umbra_by_ball ? 1 : 0;
          s.sweep_edge_beams += static_cast<double>(r.sweep_edge_beams);
          s.sweep_beams += static_cast<double>(r.sweep_beams);
          s.sweep_crossings += static_cast<double>(r.sweep_crossings);
          s.silhouette_edges += r.silhouette_edges;
          s.edge_tree_solids += r.edge_tree_solids;
          s.edge_tree_edges += static_cast<double>(r.edge_tree_edges);
          s.edge_tree_fallbacks += r.edge_tree_fallbacks;
          if (r.visible >= 1.0 - 1e-9) {
            s.lit += 1;
          } else if (r.visible <= 1e-9) {
            s.umbra += 1;
          } else {
            s.penumbra += 1;
          }
        }
        progress.advance();
      });
    }

    RowStats t;
    for (const RowStats& s : rows) {
      t.pixels += s.pixels;
      t.candidates += s.candidates;
      t.candidates_max = std::max(t.candidates_max, s.candidates_max);
      t.polygons += s.polygons;
      t.culled += s.culled;
      t.lit += s.lit;
      t.umbra += s.umbra;
      t.penumbra += s.penumbra;
      t.degenerate += s.degenerate;
      t.umbra_by_ball += s.umbra_by_ball;
      t.sweep_edge_beams += s.sweep_edge_beams;
      t.sweep_beams += s.sweep_beams;
      t.sweep_crossings += s.sweep_crossings;
      t.silhouette_edges += s.silhouette_edges;
      t.edge_tree_solids += s.edge_tree_solids;
      t.edge_tree_edges += s.edge_tree_edges;
      t.edge_tree_fallbacks += s.edge_tree_fallbacks;
    }
    Counters& c = vis.counters;
    c["pixels"] = t.pixels;
    c["candidate_triangles"] = t.candidates;
    c["candidates_per_pixel"] = t.pixels > 0 ? t.candidates / t.pixels : 0.0;
    c["candidates_max"] = t.candidates_max;
    c["projected_polygons"] = t.polygons;
    c["culled_back_faces"] = t.culled;
    c["closed_solids"] = static_cast<double>(scene.solids().size());
    c["pixels_lit"] = t.lit;
    c["pixels_umbra"] = t.umbra;
    c["pixels_penumbra"] = t.penumbra;
    c["degenerate_fallbacks"] = t.degenerate;
    c["pixels_umbra_by_ball"] = t.umbra_by_ball;
    c["sweep_edge_beams"] = t.sweep_edge_beams;
    c["sweep_beams"] = t.sweep_beams;
    c["sweep_crossings"] = t.sweep_crossings;
    c["silhouette_edges"] = t.silhouette_edges;
    c["edge_tree_silhouettes"] = t.edge_tree_solids;
    c["edge_tree_edges_tested"] = t.edge_tree_edges;
    c["edge_tree_fallbacks"] = t.edge_tree_fallbacks;
    c["edge_trees"] = static_cast<double>(scene.edge_trees().size());
    size_t balls = 0;
    for (const ExactSolid& solid : scene.solids()) balls += solid.balls.size();
    c["inner_balls"] = static_cast<double>(balls);
    c["occluder_triangles"] = static_cast<double>(scene.occluders().size());
    c["alpha_pieces"] = static_cast<double>(scene.pieces().size());
    c["bvh_nodes"] = static_cast<double>(scene.bvh().nodes().size());
    return vis;
  }

 private:
  ExactOptions options_;
  std::unique_ptr<const ExactScene> prepared_;
  double unreported_prepare_ms_ = 0.0;
};

}  // namespace

std::unique_ptr<ShadowMethod> make_exact_method(const ExactOptions& options) {
  return std::make_unique<ExactMethod>(options);
}

void register_exact(MethodRegistry& registry) {
  MethodInfo info;
  info.name = "exact";
  info.summary =
      "analytic visible fraction per pixel: occluders projected onto the light by homogeneous "
      "clipping, uncovered area by a scanline sweep over their silhouette edges (integer polygon "
      "booleans for round or textured lights and semi-opaque occluders; no samples)";
  info.reference =
      "Penumbra's analytic reference: V_coef [Forest 2008 eq. 2.10], semi-opaque occluders "
      "[Forest 2008 §4.3.3] (docs/references.md)";
  info.sample_exact = false;  // analytic: the limit raytrace converges to, not sample-equal
  info.options = {
      {"disk_segments",
       OptionType::integer,
       "256",
       "sides of the equal-area polygon standing in for a round light (|error in V| <= 0.128 "
       "(pi/N)^2)",
       {},
       16,
       1 << 20},
      {"leaf_size",
       OptionType::integer,
       "8",
       "triangles per leaf of the reference's own BVH",
       {},
       1,
       64},
      {"cull_back_faces",
       OptionType::boolean,
       "true",
       "skip the triangles of closed opaque meshes that cannot change the union (exact)",
       {},
       0,
       1},
      {"edge_trees",
       OptionType::boolean,
       "true",
       "find the silhouettes of large closed meshes from a hierarchy over their edges instead of "
       "visiting their faces (exact; with cull_back_faces)",
       {},
       0,
       1},
  };
  info.create = [](const MethodOptions& o) {
    ExactOptions options;
    options.disk_segments = o.get_int("disk_segments");
    options.leaf_size = o.get_int("leaf_size");
    options.cull_back_faces = o.get_bool("cull_back_faces");
    options.edge_trees = o.get_bool("edge_trees");
    return make_exact_method(options);
  };
  registry.add(std::move(info));
}

}  // namespace penumbra
