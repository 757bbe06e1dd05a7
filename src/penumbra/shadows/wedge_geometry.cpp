#include "penumbra/shadows/wedge_geometry.hpp"

#include <algorithm>
#include <cmath>

namespace penumbra {

namespace {

/// Side plane through `v` (an edge endpoint) with every light point behind it and the edge's
/// direction `d` (unit, pointing into the edge) in front: n = d + α·g, g the unit direction from
/// the light centre to v, α the smallest tilt that puts the whole hull behind. Any such plane
/// contains S near v [paper III §3.1]: for y = x + t(X − x), n·(y − v) = (1 − t)·n·(x − v) +
/// t·n·(X − v) ≥ 0.
bool side_plane(const DVec3& v, const DVec3& d, const std::vector<DVec3>& hull, const DVec3& centre,
                WedgePlane& out) {
  DVec3 g = v - centre;
  const double gl = glm::length(g);
  if (!(gl > 0.0)) return false;
  g /= gl;
  double alpha = 0.0;
  for (const DVec3& x : hull) {
    const double dx = glm::dot(d, x - v), gx = glm::dot(g, x - v);
    if (dx <= 0.0) continue;
    if (!(gx < 0.0)) return false;  // the hull reaches past v's plane ⟂ g: no tilt helps
    alpha = std::max(alpha, dx / -gx);
  }
  if (!(1.0 + alpha * glm::dot(g, d) > 0.0)) return false;  // the edge itself must be in front
  const DVec3 n = glm::normalize(d + alpha * g);
  for (const DVec3& x : hull)
    if (!(glm::dot(n, x - v) <= 1e-12 * glm::length(x - v)))
      return false;  // points behind along d but beyond along g
  out.n = n;
  out.d = glm::dot(n, v);
  return true;
}

}  // namespace

Wedge build_wedge(const DVec3& e0, const DVec3& e1, double weight,
                  const std::vector<DVec3>& light_hull, const DVec3& light_centre, double scale) {
  Wedge w;
  w.e0 = e0;
  w.e1 = e1;
  w.weight = weight;
  w.tolerance = 1e-9 * scale;
  const DVec3 edge = e1 - e0;
  const double len = glm::length(edge);
  if (!(len > 0.0)) return w;  // unbounded: every pixel on screen is a candidate
  const DVec3 d = edge / len;

  // Front and back planes: angles of the hull points around the edge's line, measured from the
  // direction toward the light centre (u) in the frame (u, w = d × u).
  DVec3 u = light_centre - e0;
  u -= glm::dot(u, d) * d;
  const double ul = glm::length(u);
  if (ul > 1e-12 * (len + glm::length(light_centre - e0))) {
    u /= ul;
    const DVec3 wv = glm::cross(d, u);
    double phi_min = 0.0, phi_max = 0.0;
    bool ok = true;
    for (const DVec3& x : light_hull) {
      const DVec3 y = x - e0;
      const double cu = glm::dot(y, u), cw = glm::dot(y, wv);
      // Beyond ±(π/2 − margin) the hull wraps around the line: no pair of planes bounds S.
      if (!(cu > 1e-9 * std::abs(cw))) {
        ok = false;
        break;
      }
      const double phi = std::atan2(cw, cu);
      phi_min = std::min(phi_min, phi);
      phi_max = std::max(phi_max, phi);
    }
    if (ok) {
      // Points of S lie at angle ψ ∈ [φ_min + π, φ_max + π]: sin(ψ − φ_min) ≤ 0 and
      // sin(ψ − φ_max) ≥ 0, i.e. dot(y, perp(φ)) with perp(φ) = −sin φ·u + cos φ·w.
      const DVec3 p_min = -std::sin(phi_min) * u + std::cos(phi_min) * wv;
      const DVec3 p_max = -std::sin(phi_max) * u + std::cos(phi_max) * wv;
      w.planes[w.plane_count++] = {-p_min, glm::dot(-p_min, e0)};
      w.planes[w.plane_count++] = {p_max, glm::dot(p_max, e0)};
    }
  }
  WedgePlane side;
  if (side_plane(e0, d, light_hull, light_centre, side)) w.planes[w.plane_count++] = side;
  if (side_plane(e1, -d, light_hull, light_centre, side)) w.planes[w.plane_count++] = side;
  return w;
}

}  // namespace penumbra
