// The edges depth complexity sampling integrates, and the multiplicity each one carries for a
// given receiver [Forest 2008 §4.1.2, §4.1.4; Laine 2005].
//
// Depth complexity D(p, s) = the number of caster triangles the segment p → s crosses (what
// `raytrace` tests, what the shadow-volume count gives for s = the light centre c). Seen from p,
// each triangle T blocks the part P_T of the light plane it projects onto (clipped to 0 < W ≤ 1,
// exact/projection.hpp), so D(p, s) = Σ_T [s ∈ P_T]. Walking in light uv from c to s, D changes
// by ±1 each time the walk crosses the projection of an edge of some T, entering or leaving P_T.
// Summing the triangles that share an edge e, the walk's step across e's projection is
//     m_p(e) = Σ_{faces f of e} side_f(p) · o_{f,e}
// (side_f(p): which side of f's plane p lies on; o_{f,e}: the direction f traverses e), the signed
// edge multiplicity of scene/silhouettes.hpp taken from the receiver. Nothing in this assumes a
// closed, manifold or consistently wound mesh: it is the sum of the triangles' own boundaries, so
// open, non-manifold and inconsistent edges are exact by construction (no solid heuristic).
//
// Which edges, and with which weight, without a per-pixel sweep of the whole mesh. If the
// projection of e from p meets the light at q, then p and q lie on opposite sides of every plane
// through e (the segment p → q passes through e), so m_p(e) = −m_q(e): only edges that are a
// silhouette from SOME light point matter — the silhouette w.r.t. the whole light [Forest 2008
// §4.1.4, Laine 2005], kept here when m ≠ 0 at the centre or an adjacent face's plane cuts the
// light (light_silhouette_edges). For an edge none of whose face planes cuts the light, m_q is the
// same for every light point, so its weight is the constant m_c (from the centre); only the edges
// whose face planes cut the light ("straddling") need the per-receiver sum above, which is what
// makes `light` mode exact. `centre` mode is the standard detection from the light centre, weight
// m_c for every edge: it misses edges that are silhouettes only from part of the light, the
// under-estimated penumbra of Forest fig. 4.3a.
#pragma once

#include <cstdint>
#include <vector>

#include "penumbra/core/math.hpp"
#include "penumbra/scene/light.hpp"
#include "penumbra/scene/mesh.hpp"
#include "penumbra/shadows/wedges/pass.hpp"

namespace penumbra::dcs {

enum class SilhouetteMode : uint8_t { light, centre };

/// A face plane of a straddling edge: side(p) = sign(dot(n, p) − d), with the direction the face
/// traverses the edge (±1, relative to DcsEdge from → to).
struct EdgeFace {
  DVec3 n{0.0};
  double d = 0.0;
  int32_t sign = 0;
};

struct Edge {
  DVec3 from{0.0}, to{0.0};
  /// m_c of the light centre (> 0 when nonzero: from → to is then the wedges' direction); the
  /// weight of every receiver unless the edge straddles.
  int32_t centre_multiplicity = 0;
  /// Straddling edges: their faces' planes faces[face_begin, face_begin + face_count); the
  /// receiver's weight is −Σ side · sign.
  uint32_t face_begin = 0, face_count = 0;
  uint16_t layer_class = 0;  // which counter set it updates (opaque, or one transmittance)
};

struct EdgeSet {
  std::vector<Edge> edges;
  std::vector<EdgeFace> faces;
  size_t straddling = 0;
};

/// The edges of every caster mesh (`mesh_class[m]`: the counter set of casters.meshes[m]).
EdgeSet build_edges(const wedge_pass::CasterMeshes& casters,
                    const std::vector<uint16_t>& mesh_class, const Light& light,
                    SilhouetteMode mode);

/// The edge's multiplicity for receiver point p, as seen from the light (the sign of m_q for the
/// light points q its projection covers).
inline int32_t multiplicity_for(const EdgeSet& set, const Edge& e, const DVec3& p) {
  if (e.face_count == 0) return e.centre_multiplicity;
  int32_t m = 0;
  for (uint32_t k = e.face_begin; k < e.face_begin + e.face_count; ++k) {
    const EdgeFace& f = set.faces[k];
    const double s = glm::dot(f.n, p) - f.d;
    m -= ((s > 0.0) - (s < 0.0)) * f.sign;
  }
  return m;
}

/// The weights of a list of wedges (a pixel block's bin) in a SIMD-friendly layout: per entry
/// the two face planes of a straddling edge (sign 0 and a zero plane for a boundary edge's missing
/// face), or the constant centre multiplicity. Edges with three or more faces (non-manifold) are
/// `general` and take multiplicity_for.
struct BlockWeights {
  std::vector<double> nx[2], ny[2], nz[2], d[2], sign[2], constant;
  std::vector<uint8_t> general;
  std::vector<int32_t> m;  // per entry, the weight for the last point given to `evaluate`

  void assign(const EdgeSet& set, const std::vector<uint32_t>& entries,
              const std::vector<uint32_t>& edge_of_entry);
  /// m[j] for every entry at point p.
  void evaluate(const EdgeSet& set, const std::vector<uint32_t>& entries,
                const std::vector<uint32_t>& edge_of_entry, const DVec3& p);
};

}  // namespace penumbra::dcs
