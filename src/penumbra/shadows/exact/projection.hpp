// The geometry of the exact reference: projecting occluder polygons from one receiver point onto
// the light's uv square (homogeneous clipping, no guessing for polygons that cross the receiver's
// or the light's plane), and measuring the light left visible with Clipper's exact integer
// polygon booleans.
#pragma once

#include <array>
#include <polyclipping/clipper.hpp>
#include <span>
#include <vector>

#include "penumbra/core/math.hpp"
#include "penumbra/shadows/method.hpp"

namespace penumbra {

/// Light uv [0,1] maps to Clipper integers [0, kUvScale]. 0x3FFFFFFF is the largest coordinate
/// Clipper 6 handles with 64-bit arithmetic (beyond it, it switches to slower 128-bit products);
/// it rounds vertices to ~1e-9 of the light's side, i.e. areas to ~1e-9 × the perimeter.
inline constexpr double kUvScale = 1073741823.0;
inline constexpr double kUvArea = kUvScale * kUvScale;  // the whole uv square, Clipper units²

/// Apex cut of the pyramid: occluder parts with W < kMinW — closer to the receiver than 1e-9 of its
/// distance to the light plane — are ignored. Far below the shared ray offset (1e-4 × the scene
/// diagonal, gbuffer.hpp); it only keeps the perspective divide finite.
inline constexpr double kMinW = 1e-9;

/// The map from world points to homogeneous light coordinates seen from one receiver point p.
/// With n the light plane's unit normal, D = dot(corner − p, n), s(x) = dot(x − p, n) / D and
/// (a, b) the dual basis of (edge_u, edge_v) in the light plane (a·edge_u = 1, a·edge_v = 0, ...):
///   W(x) = s(x),  U(x) = s(x)·dot(p − corner, a) + dot(x − p, a),  V(x) likewise with b.
/// All three are linear in x − p, and (U/W, V/W) is the light uv where the line from p through x
/// meets the light plane. A light point q is blocked by x iff x lies on the segment p→q, i.e.
/// 0 < W(x) ≤ 1 and (U/W, V/W) = q: clipping a polygon to 0 < W ≤ 1, 0 ≤ U ≤ W, 0 ≤ V ≤ W and
/// dividing gives exactly the set of light points it blocks.
struct LightProjection {
  DVec3 origin{0.0};
  DVec3 to_u{0.0}, to_v{0.0}, to_w{0.0};  // U = dot(x − origin, to_u), ...
  /// The pyramid's bounding planes (4 sides through p and each light edge, the light plane, the
  /// plane through p parallel to it): x is inside iff dot(n, x) ≤ d for all six.
  struct Plane {
    DVec3 n{0.0};
    double d = 0.0;
  };
  std::array<Plane, 6> planes;
  /// The six half-spaces project_polygon clips to, as f_k(x) = dot(clip_n[k], x − origin) +
  /// clip_c[k] ≥ 0: W ≥ kMinW, W ≤ kShadowSegmentEnd, U ≥ 0, U ≤ W, V ≥ 0, V ≤ W (classify_box).
  std::array<DVec3, 6> clip_n;
  std::array<double, 6> clip_c{};
  /// The same six half-spaces laid out for classify_box's vector loop (lane 6, 7: always inside).
  struct alignas(64) Lanes {
    double nx[8], ny[8], nz[8], c[8], ax[8], ay[8], az[8], ac[8];  // a: absolute values
  } lanes;

  DVec3 homogeneous(const DVec3& x) const {
    const DVec3 d = x - origin;
    return {glm::dot(d, to_u), glm::dot(d, to_v), glm::dot(d, to_w)};
  }
};

/// Sets up the projection from `receiver` onto the parallelogram corner + [0,1]·edge_u +
/// [0,1]·edge_v. Returns false when the receiver lies (to 1e-9 of the light's size) in the
/// light's plane or the parallelogram is degenerate: the caller's documented fallback.
bool make_light_projection(const DVec3& receiver, const DVec3& corner, const DVec3& edge_u,
                           const DVec3& edge_v, LightProjection& out);

/// The clip half-spaces as f(U, V, W) ≥ 0 of a homogeneous point h = (U, V, W), in the order
/// clip_polygon applies them: 0 W ≥ kMinW (the apex cut comes first so the later planes only see
/// W > 0), 1 W ≤ kShadowSegmentEnd, 2 U ≥ 0, 3 U ≤ W, 4 V ≥ 0, 5 V ≤ W.
inline double clip_value(int plane, const DVec3& h) {
  switch (plane) {
    case 0:
      return h.z - kMinW;
    case 1:  // the light end of the segment, with the tie rule (shadows/method.hpp)
      return kShadowSegmentEnd - h.z;
    case 2:
      return h.x;
    case 3:
      return h.z - h.x;
    case 4:
      return h.y;
    default:
      return h.z - h.y;
  }
}

/// Conservative box test: false only when the box lies entirely outside one of the pyramid's
/// planes (so it holds nothing that can block any light point).
bool box_meets_pyramid(const LightProjection& proj, const Vec3& lo, const Vec3& hi);

/// The box against the six half-spaces project_polygon clips to: ExactBvh::kOutside when it lies
/// outside one of them by a relative margin of 1e-9 (then nothing in it survives the clip),
/// kInside when every point lies inside all six by that margin (far above the rounding of the
/// homogeneous coordinates, so no polygon inside such a box is ever clipped), else kPartial.
int classify_box(const LightProjection& proj, const Vec3& lo, const Vec3& hi);

/// Clips the convex world polygon vertices[0..count) (count ≤ kMaxPolygon) to the pyramid and
/// writes the light-uv polygon it blocks, in Clipper units with positive orientation. Returns
/// false when that polygon is empty (or has zero area after rounding).
inline constexpr int kMaxPolygon = 8;
bool project_polygon(const LightProjection& proj, const DVec3* vertices, int count,
                     ClipperLib::Path& out);

/// A projected polygon before clean-up, in the orientation of the world polygon's vertex order:
/// n rounded light-uv points (consecutive duplicates possible) and, per point i, where the edge
/// i → i+1 comes from: edge[i] = k when it is a piece of the world edge k → k+1, kClipEdge when it
/// runs along a face of the pyramid. Two polygons sharing a world edge (opposite directions)
/// produce bit-identical pieces of it (the clip interpolates from the lexicographically smaller
/// end), which is what lets the exact reference skip the shared edges of a mesh from adjacency.
struct ClippedPolygon {
  static constexpr int kCapacity = kMaxPolygon + 8;  // each of the six clips adds at most one
  static constexpr int8_t kClipEdge = -1;
  int n = 0;
  ClipperLib::IntPoint q[kCapacity];
  int8_t edge[kCapacity];
};
/// Fills `out` (out.n = 0 when nothing is left; n may be 1 or 2 for a polygon touching the
/// pyramid in a point or segment: such chains are still closed and may be emitted).
void clip_polygon(const LightProjection& proj, const DVec3* vertices, int count,
                  ClippedPolygon& out);

/// The convex polygon with homogeneous vertices h[0, count) against the clip half-spaces, from
/// the same values clip_polygon tests: ExactBvh::kInside when every vertex passes every
/// half-space (clip_polygon returns the vertices unchanged), kOutside when all fail one (up to
/// points made by rounding on that plane, clip_polygon leaves nothing), else kPartial.
int classify_homogeneous(const DVec3* h, int count);
/// clip_polygon from the vertices' homogeneous coordinates (LightProjection::homogeneous): the
/// same output.
void clip_homogeneous(const DVec3* h, int count, ClippedPolygon& out);

/// One directed edge of a closed chain of light-uv segments.
struct DirectedEdge {
  ClipperLib::IntPoint from, to;
};
/// Closed loops with the same winding-number field as `edges`, a union of closed chains (at every
/// point as many edges arrive as leave), with every pair of opposite copies of one segment
/// removed (cancel = false keeps them: the same winding field, for edge sets known to have none
/// worth the hash). `edges` is used as scratch. The loops are written to loops[0, count), count
/// returned; `loops` only grows, so a buffer reused from pixel to pixel keeps its paths' capacity.
size_t trace_loops(std::vector<DirectedEdge>& edges, ClipperLib::Paths& loops, bool cancel = true);

/// The emitting shape in light uv: the unit square, or for round lights a regular polygon with the
/// same area as the inscribed circle (see make_light_outline for the error this causes).
struct LightOutline {
  ClipperLib::Path path;
  double area = kUvArea;  // Clipper units²
  bool round = false;
};
LightOutline make_light_outline(bool round, int disk_segments);

/// A semi-opaque occluder polygon: every light point it covers is multiplied by `transmittance`.
struct SemiPolygon {
  ClipperLib::Path path;
  double transmittance = 1.0;
};

/// One term of the visible light written as a signed combination of regions:
/// V · |light| = Σ weight · area(paths). Each term's paths are a Clipper result (outer boundaries
/// positive, holes negative), so area(paths) is the sum of the paths' signed areas.
struct LightRegion {
  ClipperLib::Paths paths;
  double weight = 1.0;
};

/// Closed loops with the same winding-number field as the positively oriented `polygons` (at every
/// point: the number of polygons covering it), with every pair of opposite copies of one directed
/// edge removed. Two projected triangles that share a mesh edge and keep their orientation
/// traverse it in opposite directions, so the interior edges of a mesh's projection vanish and a
/// sphere's hundreds of triangles become two silhouette loops: Clipper's non-zero union of the
/// loops is the union of the polygons (exactly: winding numbers add, and a cancelled pair
/// contributes nothing), at the cost of its outlines only.
ClipperLib::Paths cancel_shared_edges(std::span<const ClipperLib::Path> polygons);
/// The edges of positively oriented `polygons`, appended to `edges` (input of trace_loops).
void append_polygon_edges(std::span<const ClipperLib::Path> polygons,
                          std::vector<DirectedEdge>& edges);

/// Union (non-zero fill) of positively oriented polygons by pairwise reduction: groups of `group`
/// consecutive polygons are united, then the partial unions pairwise, so each pass sees the
/// crossings of partial outlines instead of all O(n²) crossings of the inputs' edges. Used when
/// cancel_shared_edges still leaves more than kUnionGroup loops (many separate occluders);
/// measured on the spheres scene before edge cancellation: 4.0 → 1.4 ms per pixel at group 32.
ClipperLib::Paths union_polygons(const ClipperLib::Paths& polygons, size_t group);
inline constexpr size_t kUnionGroup = 32;

/// The visible light as a signed combination of regions [Forest 2008 §4.3.3]. Opaque polygons: the
/// outline minus their union, B (weight 1). Semi-opaque polygons are grouped by transmittance t;
/// in a group, w(q) = the number of its polygons covering light point q, and the integrand
/// t^w = 1 − (1 − t) Σ_{k=1..w} t^(k−1), so
///   ∫_S t^w = area(S) − (1 − t) Σ_{k≥1} t^(k−1) · area(S ∩ {w ≥ k}).
/// The level sets {w ≥ k} come straight from Clipper: after cancel_shared_edges the loops' winding
/// number is w, k − 1 reversed copies of the uv square shift it to w − (k − 1) inside the square,
/// and the "positive" fill rule keeps w ≥ k. Each region of the combination so far is thus
/// expanded by every group (exactly; no per-polygon splitting), the levels stopping at the
/// group's deepest overlap, or once t^k < 1e-12 (the rest changes V by less than that).
/// Cost: one Clipper intersection per (region, level), i.e. Π over groups of (1 + depth) operations
/// on outlines; with one transmittance (the usual case) 1 + depth of the semi-opaque overlap.
/// `opaque_loops`: closed loops whose non-zero winding region is the union of the opaque
/// polygons (cancel_shared_edges of them, or trace_loops of their edges).
std::vector<LightRegion> visible_regions(const LightOutline& outline,
                                         std::span<const ClipperLib::Path> opaque_loops,
                                         const std::vector<SemiPolygon>& semi);

/// Signed area of paths (Clipper units²): holes subtract.
double paths_area(const ClipperLib::Paths& paths);

/// Σ over the texels of a width×height grid over light uv (row 0 at v = 0, texel (tx, ty) covering
/// [tx/w, (tx+1)/w] × [ty/h, (ty+1)/h]) of texel_weight[ty·w + tx] × area(paths ∩ texel), in uv
/// units². Visits only the texels each path's bounding box touches.
DVec3 texel_weighted_area(const ClipperLib::Paths& paths, int width, int height,
                          const std::vector<DVec3>& texel_weight);

}  // namespace penumbra
