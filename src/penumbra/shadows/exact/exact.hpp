// `exact`: the analytic reference. Per receiver point, every occluder polygon between the point
// and the light is projected onto the light's uv square (exactly, by homogeneous clipping), and
// the visible fraction is the area of the light left uncovered, measured by a scanline sweep over
// the projected silhouette's edges (union_area.hpp), or with exact integer polygon booleans
// (Clipper) for round or textured lights and semi-opaque occluders — no light samples
// (docs/methods/exact.md). It is the
// V_coef of [Forest 2008 eq. 2.10] integrated exactly: alpha-textured occluders are cut into their
// opaque texel runs, semi-opaque ones multiply by their transmittance per crossing
// [Forest 2008 §4.3.3], textured lights weight the light by texel.
//
// A receiver whose every segment to the light passes through a ball inside a closed opaque mesh is
// in umbra with nothing projected (solid_interior.hpp).
//
// It shares no candidate search with any method it judges (its own BVH, exact/bvh.hpp).
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <vector>

#include "penumbra/shadows/exact/bvh.hpp"
#include "penumbra/shadows/exact/projection.hpp"
#include "penumbra/shadows/method.hpp"

namespace penumbra {

struct ExactOptions {
  /// Sides of the equal-area polygon that stands in for a round light (error ≤ 0.128·(π/N)² in V:
  /// 1.9e-5 for 256; see make_light_outline).
  int disk_segments = 256;
  /// BVH leaf size, triangles. 8: the traversal waits on node and cone loads, so fewer, fuller
  /// leaves win (dense models 512², CPU: elephant −7 %, armadillo −6 %, dragon −7 %, herd −8 %
  /// against 4; spheres equal).
  int leaf_size = 8;
  /// Skip the triangles of opaque meshes that cannot change the union (exact: see
  /// ExactScene::solids and cull_mode in exact.cpp). False projects every triangle.
  bool cull_back_faces = true;
  /// Large closed meshes (at least kEdgeTreeMinTriangles) seen from outside: their projected
  /// silhouette is found from a hierarchy over their edges (ExactEdgeTree) instead of by visiting
  /// every kept face in the pyramid (exact: the same winding field). Needs cull_back_faces.
  bool edge_trees = true;
};

/// One shadow-casting triangle, in double precision (the float vertices convert exactly).
struct ExactOccluder {
  // The fields every candidate reads (its side of the receiver, its solid, how it blocks) first,
  // with v[0]: the back-face test then touches 64 bytes, not both ends of the record.
  /// (v1 − v0) × (v2 − v0), unnormalised: the receiver p sees the positive side where
  /// normal · (p − v0) > 0.
  DVec3 normal{0.0};
  /// Index into ExactScene::solids() when the triangle belongs to an opaque uncut mesh, else
  /// kNotSolid.
  uint32_t solid = kNotSolid;
  static constexpr uint32_t kNotSolid = 0xFFFFFFFFu;
  /// Alpha-textured triangle partly cut away by its mask: only its opaque pieces
  /// pieces()[piece_first, piece_first + piece_count) block light. False: the whole triangle.
  bool cut = false;
  /// 0: opaque. In (0, 1): every crossing multiplies the light by it (semi-opaque).
  double transmittance = 0.0;
  DVec3 v[3];
  uint32_t piece_first = 0;
  uint32_t piece_count = 0;
  /// Opaque uncut triangles: neighbour[k] is the occluder across the edge v[k] → v[k+1] when that
  /// edge (welded by bit-identical position) belongs to exactly one other triangle of the same
  /// mesh, traversing it the other way; else kNoNeighbour. Shared edges of two triangles whose
  /// projections have the same orientation cancel and are never emitted (exact_visibility).
  uint32_t neighbour[3] = {kNoNeighbour, kNoNeighbour, kNoNeighbour};
  static constexpr uint32_t kNoNeighbour = 0xFFFFFFFFu;
};

/// A ball that misses a solid's surface and caps, with a non-zero winding number over it: a segment
/// through it that ends where the winding number is 0 crosses the surface (solid_interior.hpp).
struct ExactInnerBall {
  DVec3 center{0.0};
  double radius = 0.0;
};
/// Consecutive inner balls [first, first + count) of a solid and a ball holding them all.
struct ExactBallGroup {
  ExactInnerBall bound;
  uint32_t first = 0, count = 0;
};

/// An opaque, uncut mesh made a closed surface: its triangles plus virtual caps — fans over the
/// closed walks of its boundary (the directed edges whose copies do not cancel: holes, and edges of
/// inconsistently oriented or non-manifold neighbours), oriented so that mesh + caps is a 2-cycle.
/// That cycle gives space an integer winding number w (0 far away) that every transversal crossing
/// changes by ±1, which is what lets half of the mesh's triangles be skipped wherever the pyramid
/// from the receiver to the light misses the caps (cull_mode in exact.cpp). A closed manifold has
/// no caps. The caps are never projected: they exist for the winding number and the cap test.
struct ExactSolid {
  Bounds3 box;  // of the mesh's vertices (caps included)
  uint32_t mesh = 0;
  std::vector<std::array<DVec3, 3>> caps;
  std::vector<Bounds3> cap_boxes;           // one per boundary walk
  std::vector<Bounds3> cap_triangle_boxes;  // one per cap triangle
  std::vector<ExactInnerBall> balls;        // in groups of neighbours (group_inner_balls)
  std::vector<ExactBallGroup> ball_groups;
  /// Index into ExactScene::edge_trees(), or −1 (a small mesh: its faces are visited).
  int32_t edge_tree = -1;
};
/// The normals of a BVH subtree whose triangles all belong to one ExactSolid: every unit normal
/// lies within the angle θ < 90° of `axis`; the triangles lie in the sphere of radius `radius`
/// around the centre of the node's box. Lets the culling skip the whole subtree when the receiver
/// sees all of it from the culled side (cull_mode in exact.cpp). solid = ExactOccluder::kNotSolid:
/// no cone.
/// Single precision, rounded outward (θ and the radius up), in 32 bytes: the traversal reads one
/// per node visited, and two cones share a cache line as two nodes do.
struct ExactNodeCone {
  Vec3 axis{0.0f};  // unit to float rounding (||axis| − 1| below 2e-7)
  float cos_theta = 0.0f, sin_theta = 1.0f;
  float radius = 0.0f;
  uint32_t solid = ExactOccluder::kNotSolid;
  uint32_t triangles = 0;  // in the subtree
};
static_assert(sizeof(ExactNodeCone) == 32);

/// One edge of a solid's mesh, once: face `left` (ExactEdgeTree::faces) traverses it a → b,
/// `right` (the triangle's ExactOccluder::neighbour there) b → a, or kNoNeighbour (a boundary
/// edge: a hole, or one of inconsistent or non-manifold neighbours, which never cancels).
struct ExactEdge {
  DVec3 a{0.0}, b{0.0};
  uint32_t left = 0, right = ExactOccluder::kNoNeighbour;
};
/// A face as the side tests read it: the occluder's normal and v[0], bit for bit.
struct ExactFacePlane {
  DVec3 normal{0.0}, v0{0.0};
};
/// A solid's edges in a BVH of their own (leaf order), with a normal cone per node over both faces
/// of every edge below it (solid = kNotSolid where a boundary edge lies below): a receiver that
/// sees all those faces strictly from one side has no silhouette edge there. The faces' planes are
/// copied in the order the edges first use them, so a search reads them nearly in sequence.
struct ExactEdgeTree {
  ExactBvh bvh;
  std::vector<ExactEdge> edges;
  std::vector<ExactNodeCone> cones;
  std::vector<ExactFacePlane> faces;
};
/// Solids of at least this many triangles get an edge tree: below it visiting the faces costs
/// less than the tree's extra ray per receiver.
inline constexpr size_t kEdgeTreeMinTriangles = 1024;

/// Meshes needing more cap triangles than this (large open surfaces) are not made solids: their
/// caps would be met by most pyramids and would cost every winding-number ray.
inline constexpr size_t kMaxCapTriangles = 1024;

/// A convex part of an alpha-textured triangle (at most 7 vertices: triangle ∩ texel-run
/// rectangle) where the nearest-texel mask is opaque: piece_vertices()[first, first + count).
struct ExactPiece {
  uint32_t first = 0;
  uint32_t count = 0;
};

/// The scene's occluders as the reference sees them, built once per frame: the shadow-casting
/// triangles (casts_shadows meshes, transmittance < 1), the opaque pieces of alpha-textured ones
/// and the BVH over them.
class ExactScene {
 public:
  explicit ExactScene(const Scene& scene, int leaf_size = 8, bool cull_back_faces = true,
                      bool edge_trees = true);

  const Scene& scene() const { return *scene_; }
  const std::vector<ExactOccluder>& occluders() const { return occluders_; }
  /// occluders()[t].neighbour, packed (12 bytes a triangle): the per-pixel edge cancellation and
  /// grouping read it for every kept triangle, mostly in scattered order.
  const std::vector<std::array<uint32_t, 3>>& neighbours() const { return neighbours_; }
  const std::vector<ExactPiece>& pieces() const { return pieces_; }
  const std::vector<DVec3>& piece_vertices() const { return piece_vertices_; }
  const ExactBvh& bvh() const { return bvh_; }
  /// The opaque meshes whose back faces may be culled (none when culling is off).
  const std::vector<ExactSolid>& solids() const { return solids_; }
  /// One per BVH node (empty when there are no solids).
  const std::vector<ExactNodeCone>& node_cones() const { return node_cones_; }
  /// Some occluder is semi-opaque (0 < transmittance < 1).
  bool semi_opaque() const { return semi_opaque_; }
  /// The large solids' edge trees (ExactSolid::edge_tree), and the solids that have one.
  const std::vector<ExactEdgeTree>& edge_trees() const { return edge_trees_; }
  const std::vector<uint32_t>& edge_tree_solids() const { return edge_tree_solids_; }

 private:
  const Scene* scene_;
  std::vector<ExactOccluder> occluders_;
  std::vector<std::array<uint32_t, 3>> neighbours_;
  std::vector<ExactPiece> pieces_;
  std::vector<DVec3> piece_vertices_;
  std::vector<ExactSolid> solids_;
  ExactBvh bvh_;
  std::vector<ExactNodeCone> node_cones_;
  std::vector<ExactEdgeTree> edge_trees_;
  std::vector<uint32_t> edge_tree_solids_;
  bool semi_opaque_ = false;
};

/// Everything about one light that does not depend on the receiver: its uv outline (square or
/// equal-area polygon) and, for a textured light, the RGB weight of every texel and their
/// area-weighted sum over the outline.
class ExactLight {
 public:
  ExactLight(const Scene& scene, const Light& light, int disk_segments = 256);

  const Light& light() const { return *light_; }
  const LightOutline& outline() const { return outline_; }
  bool textured() const { return texture_width_ > 0; }
  int texture_width() const { return texture_width_; }
  int texture_height() const { return texture_height_; }
  /// Per texel (row-major, row 0 at v = 0): emission texture RGB × light radiance.
  const std::vector<DVec3>& texel_weight() const { return texel_weight_; }
  /// Σ texel_weight × area(texel ∩ outline), uv units².
  const DVec3& total_weight() const { return total_weight_; }

 private:
  const Light* light_;
  LightOutline outline_;
  int texture_width_ = 0;
  int texture_height_ = 0;
  std::vector<DVec3> texel_weight_;
  DVec3 total_weight_{0.0};
};

struct ExactPointResult {
  /// Visible fraction in [0, 1]. Textured lights: of the emitted luminance (Rec. 709), the same
  /// collapse of RGB to one number as the sampling methods (light_weights.hpp).
  double visible = 1.0;
  /// Per channel visible fraction of the emitted RGB (textured lights; a channel the light does
  /// not emit in reads 1, as in light_weights.hpp). Untextured lights: visible in all three.
  DVec3 visible_rgb{1.0};
  uint32_t candidates =
      0;  // occluder triangles whose box met the pyramid (the segment: point lights)
  uint32_t polygons = 0;  // non-empty projected occluder polygons
  uint32_t culled = 0;    // candidates of closed meshes skipped as unable to change the union
  /// The receiver lies in the light's plane (or is not finite): the projection is undefined and
  /// the documented fallback V = 1 ("light touching geometry") was taken.
  bool degenerate = false;
  /// Decided in umbra by an inner ball of a solid (solid_interior.hpp), nothing projected.
  bool umbra_by_ball = false;
  /// The area sweep's work: edges crossing each of its beams, summed over every sweep (the
  /// square's union and, with many edges, the outlines of its parts; union_area.hpp).
  uint64_t sweep_edge_beams = 0;
  uint64_t sweep_beams = 0;      // the beams of those sweeps
  uint64_t sweep_crossings = 0;  // edge crossings found inside their beams
  /// Light-uv edges of the projected silhouette given to the area sweep (opaque rectangular case).
  uint32_t silhouette_edges = 0;
  /// Solids whose silhouette came from their edge trees, the edges those searches tested, and
  /// whether an unsure edge tree made the receiver be done again by its faces (edge_tree.hpp).
  uint32_t edge_tree_solids = 0;
  uint64_t edge_tree_edges = 0;
  uint32_t edge_tree_fallbacks = 0;
};

/// Carried from one receiver to the next (exact_visibility): was the previous one in umbra by the
/// inner balls? Then they are tried first — neighbours mostly share their umbra.
struct ExactUmbraHint {
  bool previous_umbra = false;
};

/// The exact visibility of `light` from the world point `receiver` (double precision throughout;
/// the light frame comes from light_frame(light.light(), receiver)).
ExactPointResult exact_visibility(const ExactScene& scene, const ExactLight& light,
                                  const Vec3& receiver, ExactUmbraHint* hint = nullptr);

/// Convenience for tests and one-off queries: builds the ExactLight on every call.
double exact_visible_fraction(const ExactScene& scene, const Light& light, Vec3 receiver,
                              int disk_segments = 256);

/// The `exact` ShadowMethod (also registered by name through register_exact).
std::unique_ptr<ShadowMethod> make_exact_method(const ExactOptions& options = {});

}  // namespace penumbra
