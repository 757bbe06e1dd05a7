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

/// The options and factory (the registry entry is register_silhouette_map).
MethodInfo silhouette_map_info();

}  // namespace penumbra::silmap
