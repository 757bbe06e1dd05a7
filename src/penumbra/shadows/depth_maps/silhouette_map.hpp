// `silhouette_map`: shadow maps with silhouette information (Valient & Bujnak) [Valient 2005 §2].
//
// Shadow-map generation [§2.1]: a standard light-space depth map (shared with shadow_map:
// receiver_fitted_depth_map), then the silhouette pass over a topology-aware mesh (TAM, §2.1): each
// face carries its three positions and the normals of its three adjacent faces (the negated face
// normal for an edge without a neighbour, so open edges are always silhouettes). Faces with a
// silhouette edge (eq. 1) are scaled about their incenter (eq. 2) so that the thick silhouette is
// covered, after the degenerate-projection correction (§2.1.1); every covered texel stores the
// signed distance to the nearest silhouette edge (positive inside the face) and that point's depth,
// merged with the LESSEQUAL depth / distance rule.
//
// Final rendering [§2.2]: per receiver point the depth-map test, the silhouette depth test and the
// bilinearly filtered edge distance, combined by one lookup of eq. 4 in a 1D gradient table (hard
// mode). Soft mode [§2.2.1]: four samples around the point, each looked up in a 2D table whose
// second coordinate is the edge-depth / point-depth ratio scaled by the light radius.
#pragma once

#include <cstdint>
#include <vector>

#include "penumbra/core/image.hpp"
#include "penumbra/raster/depth_map.hpp"
#include "penumbra/shadows/method.hpp"
#include "penumbra/shadows/registry.hpp"

namespace penumbra::silmap {

/// One TAM face [§2.1]: positions of the face and the normals of the three adjacent faces;
/// adjacent[c] belongs to the edge from corner c to corner c+1.
struct TamFace {
  DVec3 p[3];
  DVec3 normal{0.0};  // unit face normal (cross(p1−p0, p2−p0))
  DVec3 adjacent[3];
};

/// The TAM of every caster mesh: degenerate faces (zero normal) are left out; the adjacent normal
/// of an edge is the other face's normal for a manifold edge and −normal for a boundary,
/// non-manifold or inconsistently oriented edge (or a degenerate neighbour) [§2.1].
std::vector<TamFace> build_tam(const Scene& scene);

/// Silhouette test of eq. 1 for edge c of `face`, seen from `eye`.
bool is_silhouette(const TamFace& face, int c, const DVec3& eye);

/// The degenerate-projection correction of §2.1.1 on a screen triangle (texels): if the inradius
/// is below half a texel diagonal, the vertex opposite the longest edge moves away from that edge
/// (the reverse of the edge's outward normal) until it is not. Returns true if it moved a vertex.
bool correct_degenerate(DVec3 s[3]);

/// Incircle of a screen triangle (x, y only): centre and radius; radius 0 if degenerate.
void incircle(const DVec3 s[3], double& cx, double& cy, double& radius);

/// Scale factor of eq. 2: (w_o + w_sc) / w_o with w_sc = (width + 2·diagonal) / 2.
double scale_factor(double inradius, double width_texels);

/// The silhouette layer of the shadow map [§2.1.1]: per texel the signed distance (texels,
/// positive inside the occluder's faces) to the nearest silhouette edge and that point's view
/// depth (+inf: no silhouette; then the distance is ±half_band from the depth map's coverage).
struct SilhouetteLayer {
  Image<float> distance;
  Image<float> depth;
  double half_band = 1.0;  // thick-silhouette half-width, texels
  size_t silhouette_faces = 0, corrected_faces = 0;
  // Texels the silhouette pass evaluated (within a texel of a silhouette edge's half band, inside
  // its face's scaled cover): the pass's cost, bounded by the silhouettes' length × band width.
  uint64_t texels_visited = 0;
  // Faces left out as exact repeats of an earlier face (same projection, same silhouette edges).
  size_t duplicate_faces = 0;
};

SilhouetteLayer render_silhouettes(const std::vector<TamFace>& tam, const DepthMap& map,
                                   double half_band);

/// One face of the silhouette pass: projected, its silhouette edges found (eq. 1), its cover
/// corrected (§2.1.1) and scaled (eq. 2).
struct SilFace {
  DVec3 s[3];       // projected face (x, y texels; z = 1/w): the TAM's three position fields
  DVec3 scaled[3];  // scaled about the incenter (eq. 2): the rasterized cover
  int mask = 0;     // bit c: edge c → c+1 is a silhouette (eq. 1)
  // Sign of the face's side of each edge line (±1). The paper signs the distance by "inside the
  // triangle"; faces next to a silhouette are seen at grazing angles and project to slivers, so a
  // texel just inside the occluder is usually outside both of them. We sign by the half-plane of
  // the edge that holds the face (the projected opposite vertex; after the §2.1.1 correction if
  // the projection was collinear), which is the triangle test wherever the triangle is.
  double side[3] = {1.0, 1.0, 1.0};
};

/// The faces the silhouette pass rasterizes, in merge order: TAM faces with a silhouette edge seen
/// from proj.eye, in front of the light, with a cover that reaches the res² map, exact repeats
/// left out. Fills layer's silhouette_faces, corrected_faces and duplicate_faces.
std::vector<SilFace> silhouette_faces(const std::vector<TamFace>& tam, const Projection& proj,
                                      int res, double half_band, SilhouetteLayer& layer);

/// Table entries per quarter of eq. 4's coordinate, and rows of the soft table (§2.2.1).
inline constexpr int kQuarter = 256;
inline constexpr int kSoftRows = 64;

/// The lookup table of eq. 4 [§2.2], 1D (rows = 1) or 2D (soft, §2.2.1). The coordinate
/// coord = ¼(d_E + [z_O < z]) + ½[z_E < z], d_E ∈ [0, 1) the normalised edge distance, falls in
/// one of four quarters: lit, shadowed (map says so, edge behind), and twice the edge gradient.
class GradientTable {
 public:
  GradientTable(int rows, double half_band, double row_width_max, double aa_width, double offset);
  /// Eq. 4: the texture coordinate from the edge distance (texels), the two depth tests.
  double coord(double d_edge, bool occluder_in_front, bool edge_in_front) const;
  /// Linear lookup at `coord` (within its quarter, as a texture clamped per quarter) in the row
  /// for penumbra width `width` texels (ignored by a 1D table).
  double lookup(double coord, double width) const;
  /// rows × 4 quarters × (kQuarter + 1) entries, row-major.
  const std::vector<float>& values() const { return values_; }
  int rows() const { return rows_; }
  double row_width_max() const { return row_width_max_; }

 private:
  int rows_;
  double half_band_, row_width_max_;
  std::vector<float> values_;
};

/// The radius of the spherical light the soft mode assumes [§2.2.1] (a rect: the disk of the same
/// area; a point: 0).
double light_radius(const Light& light);

/// The largest view depth through `proj` of the kActive pixels' shadow origins (0 if none).
double receivers_zmax(const ShadowContext& ctx, const Projection& proj);

/// The thick silhouette's half-width (texels) and the widest penumbra (texels) for the options
/// `width` and `max_band`: soft mode with a light of `radius` > 0 widens the band to hold the
/// penumbra from the nearest caster (min_depth) to the furthest receiver (zmax, view depths).
void silhouette_band(double width, double max_band, double radius, double min_depth, double zmax,
                     double texel_tan, double& half_band, double& max_width);

/// The options and factory (the registry entry is register_silhouette_map).
MethodInfo silhouette_map_info();

}  // namespace penumbra::silmap
