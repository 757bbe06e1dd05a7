// GEARS, beyond the paper: back-face culling on closed opaque meshes. A mesh component whose
// directed edges cancel in pairs (every edge a→b matched by as many b→a: a closed, consistently
// wound surface, non-manifold joins allowed) bounds a solid with an integer winding number w that
// each transversal crossing changes by ±1 according to the side it crosses from. For a segment
// from sample P to light point X with w(P) = w(X) = 0 — both outside the solid's bounding box —
// the crossings sum to zero, so a segment that crosses the surface at all crosses some face from
// that face's positive side: the faces that have P strictly on their negative side are never
// needed to decide whether it is blocked, and the per-pixel and per-group culls drop them.
// w(P) = 0 is certified for P outside the box, and for P inside it when the ray from P away from
// the light meets no face of the solid: every face over P's cell of a depth map of the solid lies
// nearer to the light than P (the ground under a model standing on it).
#pragma once

#include <algorithm>
#include <cstdint>
#include <vector>

#include "penumbra/core/math.hpp"
#include "penumbra/scene/scene.hpp"
#include "penumbra/shadows/gears/assign.hpp"

namespace penumbra::gears {

inline constexpr int kMaxSolids = 64;             // the largest closed components, one bit each
inline constexpr uint32_t kNoSolid = kMaxSolids;  // a triangle of no solid (never culled so)

struct Solids {
  static constexpr int kMapSize = 64;  // depth-map cells per side, over each solid's box
  std::vector<uint32_t> of_triangle;   // per soup triangle: its solid, or kNoSolid
  std::vector<Vec3> lo, hi;            // per solid: its light-space box, widened
  // Per solid, kMapSize² cells over its box in x and y: the deepest z of the faces whose widened
  // xy box meets the cell (−∞: none), widened.
  std::vector<float> deepest;
  int count() const { return static_cast<int>(lo.size()); }
  /// Bit s set: w_s(p) = 0 is certified for p (unmirrored light space): outside solid s's box, or
  /// deeper than every face of s over p's depth-map cell.
  uint64_t outside(const Vec3& p) const {
    uint64_t bits = 0;
    for (int s = 0; s < count(); ++s) {
      bool out = p.x < lo[s].x || p.x > hi[s].x || p.y < lo[s].y || p.y > hi[s].y ||
                 p.z < lo[s].z || p.z > hi[s].z;
      if (!out) out = p.z > deepest[static_cast<size_t>(s) * kMapSize * kMapSize + cell(s, p)];
      bits |= uint64_t{out} << s;
    }
    return bits;
  }
  /// The depth-map cell of a point inside solid s's box (clamped).
  int cell(int s, const Vec3& p) const {
    auto index = [&](float x, float x0, float x1) {
      const float f = (x - x0) / (x1 - x0) * static_cast<float>(kMapSize);
      return std::clamp(static_cast<int>(f), 0, kMapSize - 1);  // f ≥ 0 inside the box
    };
    return index(p.y, lo[s].y, hi[s].y) * kMapSize + index(p.x, lo[s].x, hi[s].x);
  }
};

/// The closed components of a scene's opaque shadow-casting meshes (vertices welded by
/// bit-identical world position): what depends on the meshes alone, found once per scene (the
/// method's prepare). Triangles are numbered as in TriangleSoup: the shadow-casting meshes in
/// order, each one's triangles in order.
struct SolidComponents {
  std::vector<uint32_t> of_triangle;  // per triangle: its closed component, or kNoSolid
  std::vector<uint32_t> size;         // per closed component: its triangles
};

SolidComponents find_closed_components(const Scene& scene);

/// The kMaxSolids largest closed components whose light-space boxes lie on one side of the light
/// plane (every light point outside them), with their boxes (widened by 10⁻⁴ of their extent and
/// magnitude) and depth maps, in the light space of `soup` (built from the same scene).
Solids find_solids(const SolidComponents& components, const TriangleSoup& soup);
/// The same, the components found first.
Solids find_solids(const Scene& scene, const TriangleSoup& soup);

}  // namespace penumbra::gears
