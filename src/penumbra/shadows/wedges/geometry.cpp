#include "penumbra/shadows/wedges/geometry.hpp"

#include <algorithm>
#include <cmath>

namespace penumbra {

namespace {

/// Adds planes to a wedge after checking the lemma of the header: f ≤ eps on the light body (the
/// hull points, or the bounding sphere for the round construction's planes) and f ≥ −eps at both
/// top-edge endpoints a, b.
struct PlaneSink {
  const WedgeLight& light;
  Wedge& w;
  DVec3 a{0.0}, b{0.0};
  double eps = 0.0;

  /// The plane through p with normal n (any length); false if it fails the lemma.
  bool add(DVec3 n, const DVec3& p, bool sphere) {
    const double nl = glm::length(n);
    if (!(nl > 0.0) || !std::isfinite(nl)) return false;
    n /= nl;
    const double d = glm::dot(n, p);
    if (glm::dot(n, a) - d < -eps || glm::dot(n, b) - d < -eps) return false;
    if (sphere) {
      if (glm::dot(n, light.centre) - d + light.radius > eps) return false;
    } else {
      for (const DVec3& x : light.hull)
        if (glm::dot(n, x) - d > eps) return false;
    }
    for (int i = 0; i < w.plane_count; ++i)
      if (glm::dot(w.planes[i].n, n) > 1.0 - 1e-12 && std::abs(w.planes[i].d - d) <= eps)
        return true;                                    // already there
    if (w.plane_count == kMaxWedgePlanes) return true;  // dropping a plane is conservative
    w.planes[w.plane_count++] = {n, d};
    return true;
  }
};

/// Front and back planes through the line a + s·d (d unit) tangent to the light's hull points:
/// their angles around the line, measured from the direction toward the light centre (u) in the
/// frame (u, w = d × u). False when the hull wraps around the line (no such pair exists).
bool polygon_front_back(PlaneSink& sink, const DVec3& a, const DVec3& d, double ext) {
  DVec3 u = sink.light.centre - a;
  u -= glm::dot(u, d) * d;
  const double ul = glm::length(u);
  if (!(ul > 1e-12 * ext)) return false;
  u /= ul;
  const DVec3 wv = glm::cross(d, u);
  // The hull's projection along d is convex and holds the centre's (angle 0): unless it holds the
  // line's, its angles form an interval around 0 shorter than π, inside (−π, π).
  double phi_min = 0.0, phi_max = 0.0;
  for (const DVec3& x : sink.light.hull) {
    const DVec3 y = x - a;
    const double phi = std::atan2(glm::dot(y, wv), glm::dot(y, u));
    phi_min = std::min(phi_min, phi);
    phi_max = std::max(phi_max, phi);
  }
  if (!(phi_max - phi_min < kPi * (1.0 - 1e-9))) return false;  // the hull wraps the line
  // The light lies at angles [φ_min, φ_max]; the plane at angle φ has in-plane normal
  // perp(φ) = −sin φ·u + cos φ·w: −perp(φ_min) and perp(φ_max) put the light behind.
  const DVec3 p_min = -std::sin(phi_min) * u + std::cos(phi_min) * wv;
  const DVec3 p_max = -std::sin(phi_max) * u + std::cos(phi_max) * wv;
  const bool ok_min = sink.add(-p_min, a, false);
  const bool ok_max = sink.add(p_max, a, false);
  return ok_min && ok_max;
}

/// The two planes through the line a + s·d (d unit) tangent to the sphere (c, R), the sphere
/// behind: with v⊥ the part of c − a ⟂ d, ρ = |v⊥|, u = v⊥/ρ, w = d × u, the normals
/// n = −(R/ρ)·u ± √(1 − R²/ρ²)·w give n·(c − a) = −R. False if the line meets the ball.
bool sphere_front_back(PlaneSink& sink, const DVec3& a, const DVec3& d) {
  const double R = sink.light.radius;
  DVec3 v = sink.light.centre - a;
  v -= glm::dot(v, d) * d;
  const double rho = glm::length(v);
  if (!(rho > R * (1.0 + 1e-9))) return false;
  const DVec3 u = v / rho, wv = glm::cross(d, u);
  const double k = R / rho, s = std::sqrt(std::max(0.0, 1.0 - k * k));
  const bool ok0 = sink.add(-k * u + s * wv, a, true);
  const bool ok1 = sink.add(-k * u - s * wv, a, true);
  return ok0 && ok1;
}

/// Paper III §3.1's side plane through p (a top-edge endpoint): it contains the direction
/// q̂ = d × (c − p) ⟂ to both the top edge (d = (q − p)/|q − p|) and c − p, and is turned about
/// that line until it touches the sphere: with ρ = |c − p|, u = (c − p)/ρ and w = ±q̂ × u (the
/// sign that tilts toward q), n = −(R/ρ)·u + √(1 − R²/ρ²)·w. False if the sphere holds p or q
/// ends up outside.
bool sphere_side(PlaneSink& sink, const DVec3& p, const DVec3& q) {
  const double R = sink.light.radius;
  const DVec3 v = sink.light.centre - p;
  const double rho = glm::length(v);
  const double len = glm::length(q - p);
  if (!(rho > R * (1.0 + 1e-9)) || !(len > 0.0)) return false;
  const DVec3 d = (q - p) / len, u = v / rho;
  DVec3 axis = glm::cross(d, u);
  const double al = glm::length(axis);
  if (!(al > 1e-12)) return false;  // the edge points at the centre
  axis /= al;
  DVec3 wv = glm::cross(axis, u);
  if (glm::dot(wv, d) < 0.0) wv = -wv;
  const double k = R / rho, s = std::sqrt(std::max(0.0, 1.0 - k * k));
  return sink.add(-k * u + s * wv, p, true);
}

/// The faces of the end pyramid at p (rays p − x_k: the light hull reflected through p) that face
/// away from the other endpoint [Assarsson 2003 IV §4.1]: every plane through p and two rays with
/// all rays on its positive side, kept iff the other endpoint is on it too (PlaneSink checks both).
void pyramid_faces(PlaneSink& sink, const DVec3& p) {
  const std::vector<DVec3>& h = sink.light.hull;
  for (size_t i = 0; i < h.size(); ++i) {
    for (size_t j = i + 1; j < h.size(); ++j) {
      const DVec3 ri = p - h[i], rj = p - h[j];
      const DVec3 n = glm::cross(ri, rj);
      if (!(glm::length(n) > 1e-12 * glm::length(ri) * glm::length(rj))) continue;
      if (!sink.add(n, p, false)) sink.add(-n, p, false);
    }
  }
}

/// Paper IV §4.1: an edge meeting a one-sided light is clipped to the emitting side. Returns true
/// if the (closed) segment meets the light, with [a, b] clipped to h ≥ 0 when that leaves a
/// segment.
bool clip_to_light(const WedgeLight& L, DVec3& a, DVec3& b) {
  const double ha = glm::dot(L.normal, a - L.centre), hb = glm::dot(L.normal, b - L.centre);
  if ((ha > 0.0 && hb > 0.0) || (ha < 0.0 && hb < 0.0) || ha == hb) return false;
  const DVec3 q = a + (ha / (ha - hb)) * (b - a);
  if (L.disk) {
    if (!(glm::length(q - L.centre) <= L.radius * (1.0 + 1e-9))) return false;
  } else {
    const DVec3 r = q - L.corner;
    const double uu = glm::dot(L.edge_u, L.edge_u), uv = glm::dot(L.edge_u, L.edge_v),
                 vv = glm::dot(L.edge_v, L.edge_v), det = uu * vv - uv * uv;
    if (!(det > 0.0)) return false;
    const double su = glm::dot(r, L.edge_u), sv = glm::dot(r, L.edge_v);
    const double al = (vv * su - uv * sv) / det, be = (uu * sv - uv * su) / det;
    const double m = 1e-9;
    if (!(al >= -m && al <= 1.0 + m && be >= -m && be <= 1.0 + m)) return false;
  }
  // Keep the emitting part unless it is a single point (then nothing on the emitting side can be
  // shadowed by the edge; the lemma still bounds the back side).
  if (ha < 0.0 && hb > 0.0) a = q;
  if (hb < 0.0 && ha > 0.0) b = q;
  return true;
}

}  // namespace

Wedge build_wedge(const DVec3& e0, const DVec3& e1, double weight, const WedgeLight& light,
                  WedgeConstruction construction, double scale) {
  Wedge w;
  w.e0 = w.top0 = e0;
  w.e1 = w.top1 = e1;
  w.weight = weight;
  w.tolerance = 1e-9 * scale;
  if (!(glm::length(e1 - e0) > 0.0) || light.hull.empty()) {
    w.degenerate = true;  // unbounded: every pixel of its screen bound is a candidate
    return w;
  }
  DVec3 a = e0, b = e1;
  const bool touches = light.one_sided && clip_to_light(light, a, b);
  const DVec3& c = light.centre;

  // Paper III §3.1: move the farther vertex toward the centre to the nearer one's distance (kept
  // as it is when the nearer one is at the centre: the lemma needs s > 0).
  if (construction == WedgeConstruction::paper) {
    const double ra = glm::length(a - c), rb = glm::length(b - c);
    if (ra > rb && rb > 1e-9 * ra)
      a = c + (rb / ra) * (a - c);
    else if (rb > ra && ra > 1e-9 * rb)
      b = c + (ra / rb) * (b - c);
  }
  w.top0 = a;
  w.top1 = b;

  double ext = glm::length(a - c) + glm::length(b - c) + light.radius;
  for (const DVec3& x : light.hull) ext = std::max(ext, glm::length(x - c));
  PlaneSink sink{light, w, a, b, 1e-12 * ext};

  const double len = glm::length(b - a);
  bool missing = touches;
  if (!(len > 1e-12 * ext)) {
    // A single cone (Assarsson 2003 III fig. 4b): the pyramid of the light hull at the top edge.
    pyramid_faces(sink, b);
  } else if (construction == WedgeConstruction::paper && light.round) {
    const DVec3 d = (b - a) / len;
    missing |= !sphere_front_back(sink, a, d);
    missing |= !sphere_side(sink, a, b);
    missing |= !sphere_side(sink, b, a);
  } else {
    missing |= !polygon_front_back(sink, a, (b - a) / len, ext);
    pyramid_faces(sink, a);
    pyramid_faces(sink, b);
  }
  if (touches)
    sink.add(light.normal, c, false);  // the emitting half-space (Assarsson 2003 IV §4.1)
  w.degenerate = missing;
  return w;
}

}  // namespace penumbra
