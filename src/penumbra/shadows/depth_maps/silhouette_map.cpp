// `silhouette_map`: shadow maps with silhouette information [Valient 2005 §2; Valient & Bujnak].
// See depth_maps/silhouette_map.hpp and docs/methods/silhouette_map.md.
//
// Stages of compute():
//  1. depth map from the light point (the light centre), fitted to the receivers — the same map
//     shadow_map renders [§2.1, first step];
//  2. TAM of every caster (build_tam, §2.1) and the silhouette pass (render_silhouettes, §2.1.1):
//     eq. 1 per face edge, degenerate-projection correction, scaling about the incenter (eq. 2),
//     per texel signed distance + depth of the nearest silhouette point, LESSEQUAL merge;
//  3. per kActive pixel: hard mode = one lookup of eq. 4 in the 1D gradient table (§2.2); soft
//     mode = four lookups in the 2D table indexed by the scaled edge/point depth ratio (§2.2.1).
#include "penumbra/shadows/depth_maps/silhouette_map.hpp"

#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <utility>

#include "penumbra/core/parallel.hpp"
#include "penumbra/raster/projection.hpp"
#include "penumbra/render/receivers.hpp"
#include "penumbra/scene/edges.hpp"
#include "penumbra/shadows/depth_maps/shadow_map.hpp"
#include "penumbra/shadows/wedges/shadow_volume.hpp"

namespace penumbra::silmap {

namespace {

constexpr double kDiagonal = 1.4142135623730951;  // one texel's diagonal, texels
constexpr int kBand = 16;

double edge_fn(const DVec3& a, const DVec3& b, double x, double y) {
  return (b.x - a.x) * (y - a.y) - (b.y - a.y) * (x - a.x);
}

/// Visibility of a point at signed distance d (texels, > 0 inside the occluder) from a straight
/// edge, for a light whose image there is a disk of diameter `width` texels: the lit fraction of
/// the disk. width 0: a step. This is the "cosine-like" content of the lookup tables [§2.2.1].
double disk_profile(double d, double width) {
  if (!(width > 1e-9)) return d > 0.0 ? 0.0 : 1.0;
  const double x = std::clamp(d / (0.5 * width), -1.0, 1.0);
  return (std::acos(x) - x * std::sqrt(std::max(0.0, 1.0 - x * x))) / kPi;
}

/// The columns of row `y` (texel centres at y + ½) within `radius` texels of the face's
/// silhouette edges: per edge, the row's cut through the rectangle around the segment (the
/// segment lengthened by `radius` at both ends, `radius` to either side), which holds the
/// segment's capsule; emit(x_lo, x_hi) once per disjoint range. A texel of a thick silhouette
/// lies within half_band of a silhouette edge, so only these columns can take one: the rest of a
/// large face's cover is neither visited nor written (its cost was its area, ~5 ms per face of
/// a 2048² map, for every face of a stack).
template <typename Emit>
void silhouette_spans(const SilFace& f, double radius, int res, int y, Emit&& emit) {
  const double py = y + 0.5;
  double lo[3], hi[3];
  int count = 0;
  for (int c = 0; c < 3; ++c) {
    if (!(f.mask & (1 << c))) continue;
    const DVec3 &a = f.s[c], &b = f.s[(c + 1) % 3];
    const double ex = b.x - a.x, ey = b.y - a.y, len = std::hypot(ex, ey);
    double x0 = -1.0, x1 = res + 1.0;
    // a ≤ k·x + m ≤ b as an x range (k = 0: all or nothing), intersected into [x0, x1].
    const auto clip = [&](double k, double m, double lower, double upper) {
      if (std::abs(k) < 1e-12) {
        if (m < lower || m > upper) x1 = x0 - 1.0;
        return;
      }
      const double u = (lower - m) / k, v = (upper - m) / k;
      x0 = std::max(x0, std::min(u, v));
      x1 = std::min(x1, std::max(u, v));
    };
    if (len < 1e-12) {
      clip(1.0, -a.x, -radius, radius);
      clip(0.0, py - a.y, -radius, radius);
    } else {
      const double ux = ex / len, uy = ey / len;
      clip(ux, (py - a.y) * uy - a.x * ux, -radius, len + radius);  // along the edge
      clip(-uy, (py - a.y) * ux + a.x * uy, -radius, radius);       // across it
    }
    if (!(x0 <= x1)) continue;
    lo[count] = std::ceil(x0 - 0.5);
    hi[count] = std::floor(x1 - 0.5);
    ++count;
  }
  // Sort the (at most three) ranges by start, then merge those that overlap or touch.
  for (int i = 1; i < count; ++i)
    for (int j = i; j > 0 && lo[j] < lo[j - 1]; --j) {
      std::swap(lo[j], lo[j - 1]);
      std::swap(hi[j], hi[j - 1]);
    }
  for (int i = 0; i < count;) {
    double end = hi[i];
    int j = i + 1;
    while (j < count && lo[j] <= end + 1.0) end = std::max(end, hi[j++]);
    const double first = std::max(lo[i], 0.0), last = std::min(end, res - 1.0);
    if (first <= last) emit(static_cast<int>(first), static_cast<int>(last));
    i = j;
  }
}

/// Removes the faces whose projection and silhouette edges repeat an earlier face's bit for bit
/// (a model instanced many times in one place: 5 000 copies of a box), which made the pass cost
/// copies × band. A copy offers every texel its original's candidate again; merging a candidate
/// twice changes nothing unless a third face's candidate, merged in between, lies where the
/// merge's 1 % depth tolerance is not symmetric (depths 1.0100–1.0101 × apart: the tolerance is
/// relative to the incoming depth), where the copy could win the tie back. The first of each set
/// stays, in order; no frame of the tests' scenes changes.
void drop_duplicate_faces(std::vector<SilFace>& faces, size_t& dropped) {
  const auto key_less = [&](uint32_t a, uint32_t b) {
    if (faces[a].mask != faces[b].mask) return faces[a].mask < faces[b].mask;
    const int order = std::memcmp(faces[a].s, faces[b].s, sizeof faces[a].s);
    return order != 0 ? order < 0 : a < b;
  };
  std::vector<uint32_t> order(faces.size());
  for (uint32_t i = 0; i < order.size(); ++i) order[i] = i;
  std::sort(order.begin(), order.end(), key_less);
  std::vector<bool> duplicate(faces.size(), false);
  for (size_t k = 1; k < order.size(); ++k) {
    const SilFace &prev = faces[order[k - 1]], &cur = faces[order[k]];
    duplicate[order[k]] = prev.mask == cur.mask && std::memcmp(prev.s, cur.s, sizeof cur.s) == 0;
  }
  size_t kept = 0;
  for (size_t i = 0; i < faces.size(); ++i)
    if (!duplicate[i]) faces[kept++] = faces[i];
  dropped = faces.size() - kept;
  faces.resize(kept);
}

}  // namespace

GradientTable::GradientTable(int rows, double half_band, double row_width_max, double aa_width,
                             double offset)
    : rows_(rows), half_band_(half_band), row_width_max_(row_width_max) {
  values_.assign(static_cast<size_t>(rows) * 4 * (kQuarter + 1), 0.0f);
  for (int r = 0; r < rows; ++r) {
    // Hard table: a linear ramp aa_width texels wide. Soft rows: disk profile of the row's width.
    const double width = rows == 1 ? 0.0 : row_width_max * r / (rows - 1);
    for (int k = 0; k < 4; ++k)
      for (int m = 0; m <= kQuarter; ++m) {
        const double d = -half_band + 2.0 * half_band * m / kQuarter + offset;
        double v = k == 0 ? 1.0 : 0.0;
        if (k >= 2) {
          if (rows == 1)
            v = aa_width > 0.0 ? std::clamp(0.5 - d / aa_width, 0.0, 1.0) : (d > 0 ? 0.0 : 1.0);
          else
            v = disk_profile(d, std::max(width, aa_width));
          // The boundary window (§2.2's offset between the silhouette boundary and the depth
          // map's): the depth test at the nearest texel centre can disagree with the point only
          // within half a texel diagonal (+ half the ramp or penumbra) of the edge. Beyond it
          // the depth map decides, so an edge of another, nearer occluder (overlapping
          // silhouettes, the "touched silhouettes" of §2.2.1) cannot light an occluded texel.
          const double window = 0.5 * kDiagonal + 0.5 * std::max(width, aa_width) + 0.25;
          if (k == 2 && d > window) v = 1.0;
          if (k == 3 && d < -window) v = 0.0;
        }
        values_[(static_cast<size_t>(r) * 4 + k) * (kQuarter + 1) + m] = static_cast<float>(v);
      }
  }
}

double GradientTable::coord(double d_edge, bool occluder_in_front, bool edge_in_front) const {
  const double dn = std::clamp((d_edge + half_band_) / (2.0 * half_band_), 0.0, 1.0 - 1e-9);
  return 0.25 * (dn + (occluder_in_front ? 1.0 : 0.0)) + 0.5 * (edge_in_front ? 1.0 : 0.0);
}

double GradientTable::lookup(double coord, double width) const {
  const double c4 = std::clamp(coord, 0.0, 1.0 - 1e-12) * 4.0;
  const int k = std::min(3, static_cast<int>(std::floor(c4)));
  const double u = (c4 - k) * kQuarter;
  const int m = std::min(kQuarter - 1, static_cast<int>(std::floor(u)));
  const double f = u - m;
  int r = 0;
  if (rows_ > 1 && row_width_max_ > 0.0)
    r = std::clamp(static_cast<int>(std::lround(width / row_width_max_ * (rows_ - 1))), 0,
                   rows_ - 1);
  const float* q = &values_[(static_cast<size_t>(r) * 4 + k) * (kQuarter + 1)];
  return (1.0 - f) * q[m] + f * q[m + 1];
}

std::vector<TamFace> build_tam(const Scene& scene) {
  std::vector<TamFace> tam;
  for (const Mesh& mesh : scene.meshes) {
    if (!mesh.casts_shadows) continue;
    const MeshEdges edges = build_mesh_edges(mesh);
    const size_t n = mesh.triangle_count();
    std::vector<DVec3> normal(n, DVec3(0.0));
    for (size_t f = 0; f < n; ++f) {
      const DVec3 p0(mesh.vertex(f, 0)), p1(mesh.vertex(f, 1)), p2(mesh.vertex(f, 2));
      const DVec3 c = glm::cross(p1 - p0, p2 - p0);
      const double len = glm::length(c);
      if (len > 0.0 && std::isfinite(len)) normal[f] = c / len;
    }
    for (size_t f = 0; f < n; ++f) {
      if (normal[f] == DVec3(0.0)) continue;  // zero-area face: casts nothing
      TamFace t;
      for (int c = 0; c < 3; ++c) t.p[c] = DVec3(mesh.vertex(f, c));
      t.normal = normal[f];
      for (int c = 0; c < 3; ++c) {
        // §2.1: the neighbour's normal, or −n_f for an edge without (exactly one, consistently
        // oriented) neighbour, so that such an edge is always a silhouette.
        t.adjacent[c] = -normal[f];
        if (!edges.face_valid(f)) continue;
        const MeshEdge& e = edges.edges[edges.face_edges[f][c]];
        if (e.kind != EdgeKind::manifold || e.face_count != 2) continue;
        for (uint32_t k = 0; k < 2; ++k) {
          const uint32_t g = edges.edge_faces[e.face_begin + k].face;
          if (g != f && g < n && normal[g] != DVec3(0.0)) t.adjacent[c] = normal[g];
        }
      }
      tam.push_back(t);
    }
  }
  return tam;
}

bool is_silhouette(const TamFace& face, int c, const DVec3& eye) {
  // Eq. 1: sign(n_f · v_EYE) ≠ sign(n_E · v_EYE), v_EYE from the edge toward the light point.
  const DVec3 v = eye - 0.5 * (face.p[c] + face.p[(c + 1) % 3]);
  const double a = glm::dot(face.normal, v), b = glm::dot(face.adjacent[c], v);
  return (a > 0.0) != (b > 0.0) || (a < 0.0) != (b < 0.0);
}

void incircle(const DVec3 s[3], double& cx, double& cy, double& radius) {
  const double la = std::hypot(s[1].x - s[2].x, s[1].y - s[2].y);  // opposite vertex 0
  const double lb = std::hypot(s[2].x - s[0].x, s[2].y - s[0].y);
  const double lc = std::hypot(s[0].x - s[1].x, s[0].y - s[1].y);
  const double p = la + lb + lc;
  const double area2 = std::abs(edge_fn(s[0], s[1], s[2].x, s[2].y));
  if (!(p > 0.0) || !std::isfinite(p)) {
    cx = s[0].x;
    cy = s[0].y;
    radius = 0.0;
    return;
  }
  cx = (la * s[0].x + lb * s[1].x + lc * s[2].x) / p;
  cy = (la * s[0].y + lb * s[1].y + lc * s[2].y) / p;
  radius = area2 / p;  // r = 2A / perimeter, area2 = 2A
}

bool correct_degenerate(DVec3 s[3]) {
  const double target = 0.5 * kDiagonal;  // §2.1.1: inradius below half a texel diagonal
  double cx, cy, r;
  incircle(s, cx, cy, r);
  if (r >= target) return false;
  // Longest edge (a, b) and its opposite vertex.
  int best = 0;
  double best_len = -1.0;
  for (int c = 0; c < 3; ++c) {
    const DVec3 &a = s[c], &b = s[(c + 1) % 3];
    const double len = std::hypot(b.x - a.x, b.y - a.y);
    if (len > best_len) {
      best_len = len;
      best = c;
    }
  }
  DVec3& v = s[(best + 2) % 3];
  if (!(best_len > 1e-9)) {
    // All three corners on one point: open a tiny right triangle around it.
    s[(best + 1) % 3].x += 2.0 * kDiagonal;
    v.y += 2.0 * kDiagonal;
    return true;
  }
  // Moving v alone gives at most r = L/2: lengthen a longest edge shorter than 4·target about its
  // midpoint first (the triangle still contains the original one: v's foot lies on the edge).
  if (best_len < 4.0 * target) {
    DVec3& a0 = s[best];
    DVec3& b0 = s[(best + 1) % 3];
    const double k = 0.5 * (4.0 * target / best_len - 1.0);
    const DVec3 e = b0 - a0;
    a0.x -= k * e.x;
    a0.y -= k * e.y;
    b0.x += k * e.x;
    b0.y += k * e.y;
    best_len = 4.0 * target;
  }
  const DVec3 a = s[best], b = s[(best + 1) % 3];
  // Unit normal of the edge (a, b) toward v: the reverse of the edge's outward normal. For a
  // collinear v either side is fine.
  DVec3 nrm(-(b.y - a.y) / best_len, (b.x - a.x) / best_len, 0.0);
  double h = nrm.x * (v.x - a.x) + nrm.y * (v.y - a.y);
  if (h < 0.0) {
    nrm = -nrm;
    h = -h;
  }
  // r = L·h / P grows with h: raise h until r ≥ target (a few fixed-point steps suffice).
  for (int it = 0; it < 16 && r < target; ++it) {
    const double p = best_len + std::hypot(v.x - a.x, v.y - a.y) + std::hypot(v.x - b.x, v.y - b.y);
    const double want = 1.01 * target * p / best_len;
    v.x += nrm.x * (want - h);
    v.y += nrm.y * (want - h);
    h = want;
    incircle(s, cx, cy, r);
  }
  return true;
}

double scale_factor(double inradius, double width_texels) {
  const double w_s = width_texels + 2.0 * kDiagonal;  // §2.1.1: width + two texel diagonals
  const double w_sc = 0.5 * w_s;
  return (inradius + w_sc) / inradius;  // eq. 2
}

std::vector<SilFace> silhouette_faces(const std::vector<TamFace>& tam, const Projection& proj,
                                      int res, double half_band, SilhouetteLayer& layer) {
  const DVec3 eye = proj.eye;
  std::vector<SilFace> faces;
  for (const TamFace& t : tam) {
    SilFace f;
    for (int c = 0; c < 3; ++c) f.mask |= is_silhouette(t, c, eye) ? (1 << c) : 0;
    // §2.1.1: a face without a silhouette edge is rejected before rasterization.
    if (f.mask == 0) continue;
    bool ok = true;
    for (int c = 0; c < 3 && ok; ++c) {
      const DVec4 clip = proj.to_clip(DVec4(t.p[c], 1.0));
      ok = clip.w > 1e-9 && std::isfinite(clip.w);  // no near clipping: skip faces behind the light
      if (ok) f.s[c] = proj.to_screen(clip);
    }
    if (!ok) continue;
    ++layer.silhouette_faces;
    double original_side[3];
    for (int c = 0; c < 3; ++c) {
      const DVec3 &a = f.s[c], &b = f.s[(c + 1) % 3], &o = f.s[(c + 2) % 3];
      original_side[c] = edge_fn(a, b, o.x, o.y);
    }
    // Degenerate after projection: correct before incenter and scaling (§2.1.1). The corrected
    // triangle only bounds what is rasterized; distances and depths use the face's own positions
    // (the pixel shader reads the three position fields, §2.1).
    DVec3 cover[3] = {f.s[0], f.s[1], f.s[2]};
    layer.corrected_faces += correct_degenerate(cover) ? 1 : 0;
    for (int c = 0; c < 3; ++c) {
      const DVec3 &a = cover[c], &b = cover[(c + 1) % 3], &o = cover[(c + 2) % 3];
      const double e = original_side[c] != 0.0 ? original_side[c] : edge_fn(a, b, o.x, o.y);
      f.side[c] = e >= 0.0 ? 1.0 : -1.0;
    }
    double cx, cy, r;
    incircle(cover, cx, cy, r);
    if (!(r > 0.0)) continue;
    const double k = scale_factor(r, 2.0 * half_band);  // width = 2·half_band texels
    for (int c = 0; c < 3; ++c)
      f.scaled[c] = DVec3(cx + k * (cover[c].x - cx), cy + k * (cover[c].y - cy), cover[c].z);
    const double xmin = std::min({f.scaled[0].x, f.scaled[1].x, f.scaled[2].x});
    const double xmax = std::max({f.scaled[0].x, f.scaled[1].x, f.scaled[2].x});
    const double ymin = std::min({f.scaled[0].y, f.scaled[1].y, f.scaled[2].y});
    const double ymax = std::max({f.scaled[0].y, f.scaled[1].y, f.scaled[2].y});
    if (xmax < 0 || ymax < 0 || xmin > res || ymin > res) continue;
    faces.push_back(f);
  }
  drop_duplicate_faces(faces, layer.duplicate_faces);
  return faces;
}

SilhouetteLayer render_silhouettes(const std::vector<TamFace>& tam, const DepthMap& map,
                                   double half_band) {
  const int res = map.resolution();
  SilhouetteLayer layer;
  layer.half_band = half_band;
  layer.distance = Image<float>(res, res, 0.0f);
  layer.depth = Image<float>(res, res, kInfinity);
  const std::vector<SilFace> faces = silhouette_faces(tam, map.proj, res, half_band, layer);

  const int bands = (res + kBand - 1) / kBand;
  std::vector<std::vector<uint32_t>> bins(bands);
  for (uint32_t i = 0; i < faces.size(); ++i) {
    const SilFace& f = faces[i];
    const double ymin = std::min({f.scaled[0].y, f.scaled[1].y, f.scaled[2].y});
    const double ymax = std::max({f.scaled[0].y, f.scaled[1].y, f.scaled[2].y});
    const int b0 = std::clamp(static_cast<int>(std::floor((ymin - 0.5) / kBand)), 0, bands - 1);
    const int b1 = std::clamp(static_cast<int>(std::floor((ymax + 0.5) / kBand)), 0, bands - 1);
    for (int b = b0; b <= b1; ++b) bins[b].push_back(i);
  }
  // One texel of margin around the half band: the spans are conservative, the distance test
  // below decides.
  const double span_radius = half_band + 1.0;
  std::atomic<uint64_t> texels_visited{0};
  parallel_bands(res, kBand, [&](int first, int last) {
    uint64_t visited = 0;
    for (uint32_t i : bins[first / kBand]) {
      const SilFace& f = faces[i];
      const auto spans = [&](int y, auto&& emit) {
        silhouette_spans(f, span_radius, res, y, emit);
      };
      rasterize_triangle_spans(
          f.scaled[0], f.scaled[1], f.scaled[2], res, first, last, spans,
          [&](int x, int y, double) {
            ++visited;
            const double qx = x + 0.5, qy = y + 0.5;
            auto inside_face = [&](double px, double py) {
              const double o = edge_fn(f.s[0], f.s[1], f.s[2].x, f.s[2].y) >= 0.0 ? 1.0 : -1.0;
              for (int c = 0; c < 3; ++c)
                if (o * edge_fn(f.s[c], f.s[(c + 1) % 3], px, py) < 0.0) return false;
              return true;
            };
            double best = kInfinity, best_inv_w = 0.0;
            bool inside = false;
            for (int c = 0; c < 3; ++c) {
              if (!(f.mask & (1 << c))) continue;
              // Nearest point of the silhouette edge (a capsule around the segment).
              const DVec3 &a = f.s[c], &b = f.s[(c + 1) % 3];
              const double ex = b.x - a.x, ey = b.y - a.y, len2 = ex * ex + ey * ey;
              const double t =
                  len2 > 0.0 ? std::clamp(((qx - a.x) * ex + (qy - a.y) * ey) / len2, 0.0, 1.0)
                             : 0.0;
              const double dist = std::hypot(qx - a.x - t * ex, qy - a.y - t * ey);
              if (dist < best) {
                best = dist;
                best_inv_w = a.z + t * (b.z - a.z);  // 1/w is linear in screen space
                // Positive on the face's side of the edge line (see SilFace::side); past the
                // segment's ends (a capsule cap) the paper's inside-the-triangle test, which
                // keeps the exterior wedge of a convex silhouette corner negative.
                inside = t > 0.0 && t < 1.0 ? f.side[c] * edge_fn(a, b, qx, qy) >= 0.0
                                            : inside_face(qx, qy);
              }
            }
            if (!(best <= half_band) || !(best_inv_w > 0.0)) return;  // not the thick silhouette
            const float depth = static_cast<float>(1.0 / best_inv_w);
            const float d = static_cast<float>(inside ? best : -best);
            float& zd = layer.depth(x, y);
            float& dd = layer.distance(x, y);
            // LESSEQUAL depth and distance tests (§2.1.1): the nearer silhouette wins; within a
            // 1 % depth tolerance (capsules of one silhouette chain) the smaller |distance| wins.
            const float tol = 0.01f * depth;
            if (depth < zd - tol || (depth <= zd + tol && std::abs(d) < std::abs(dd))) {
              zd = depth;
              dd = d;
            }
          });
    }
    texels_visited.fetch_add(visited, std::memory_order_relaxed);
  });
  layer.texels_visited = texels_visited.load();
  // Texels off every thick silhouette: the clamped distance of the depth map's coverage.
  for (int y = 0; y < res; ++y)
    for (int x = 0; x < res; ++x)
      if (layer.depth(x, y) == kInfinity)
        layer.distance(x, y) =
            static_cast<float>(map.depth(x, y) < kInfinity ? half_band : -half_band);
  return layer;
}

double light_radius(const Light& light) {
  switch (light.shape) {
    case LightShape::point:
      return 0.0;
    case LightShape::disk:
    case LightShape::sphere:
      return light.radius;
    case LightShape::rect:
      return std::sqrt(static_cast<double>(light.area()) / kPi);  // the disk of the same area
  }
  return 0.0;
}

double receivers_zmax(const ShadowContext& ctx, const Projection& proj) {
  const GBuffer& g = ctx.gbuffer;
  double zmax = 0.0;
  for (size_t i = 0; i < g.pixel_count(); ++i) {
    if (ctx.receivers[i] != kActive) continue;
    const DVec4 c = proj.to_clip(DVec4(DVec3(g.shadow_origin(i)), 1.0));
    if (c.w > 0.0) zmax = std::max(zmax, c.w);  // DepthMap::project's view depth
  }
  return zmax;
}

void silhouette_band(double width, double max_band, double radius, double min_depth, double zmax,
                     double texel_tan, double& half_band, double& max_width) {
  half_band = std::max(0.5 * width, 1.0);
  max_width = 0.0;
  if (radius > 0.0 && min_depth < kInfinity) {
    if (zmax > min_depth) max_width = 2.0 * radius * (1.0 / min_depth - 1.0 / zmax) / texel_tan;
    half_band = std::clamp(0.5 * max_width + 2.0, half_band, std::max(half_band, max_band));
  }
}

namespace {

class SilhouetteMap final : public ShadowMethod {
 public:
  explicit SilhouetteMap(const MethodOptions& o)
      : map_(DepthMapSettings::from(o)),
        soft_(o.get_choice("mode") == "soft"),
        width_(o.get_real("width")),
        aa_(o.get_real("aa_width")),
        offset_(o.get_real("offset")),
        max_band_(o.get_real("max_band")) {}

  Visibility compute(const ShadowContext& ctx) override {
    const GBuffer& g = ctx.gbuffer;
    Visibility vis;
    vis.lit = Image<float>(g.width, g.height, 1.0f);
    const DepthMap map = map_.render_from_light_centre(ctx, vis.times);

    // Soft mode: the band must hold the widest penumbra (nearest caster, furthest receiver).
    const double radius = soft_ ? light_radius(ctx.light) : 0.0;
    double half_band = 0.0, max_width = 0.0;
    const double zmax =
        radius > 0.0 && map.min_depth < kInfinity ? receivers_zmax(ctx, map.proj) : 0.0;
    silhouette_band(width_, max_band_, radius, map.min_depth, zmax, map.texel_tan, half_band,
                    max_width);

    auto start = std::chrono::steady_clock::now();
    const std::vector<TamFace> tam = build_tam(ctx.scene);
    const SilhouetteLayer layer = render_silhouettes(tam, map, half_band);
    vis.times.add("silhouettes", elapsed_ms(start));

    start = std::chrono::steady_clock::now();
    // Eq. 4's table: 1D (hard, §2.2) or 2D over the penumbra width of one of four samples (soft,
    // §2.2.1): each sample sees half the penumbra, the four spread over the other half.
    const double row_max = std::max(1.0, std::min(max_width, 2.0 * half_band) * 0.5);
    const GradientTable table(radius > 0.0 ? kSoftRows : 1, half_band, row_max, aa_, offset_);
    const int res = map.resolution();
    const double hb = half_band;
    // Bilinearly filtered edge distance (the paper's hardware filtering, [Bujnak 2004]).
    auto edge_distance = [&](double sx, double sy) {
      const double fx = sx - 0.5, fy = sy - 0.5;
      const int x0 = static_cast<int>(std::floor(fx)), y0 = static_cast<int>(std::floor(fy));
      const double ax = fx - x0, ay = fy - y0;
      auto at = [&](int x, int y) -> double {
        if (x < 0 || y < 0 || x >= res || y >= res) return -hb;
        return layer.distance(x, y);
      };
      return (1 - ay) * ((1 - ax) * at(x0, y0) + ax * at(x0 + 1, y0)) +
             ay * ((1 - ax) * at(x0, y0 + 1) + ax * at(x0 + 1, y0 + 1));
    };
    auto edge_depth = [&](double sx, double sy) -> double {
      const int x = static_cast<int>(std::floor(sx)), y = static_cast<int>(std::floor(sy));
      if (x < 0 || y < 0 || x >= res || y >= res) return kInfinity;
      return layer.depth(x, y);
    };
    parallel_rows(g.height, [&](int y) {
      ShadowMapLookup look(map, map_.bias, map_.slope_bias);
      for (int x = 0; x < g.width; ++x) {
        const size_t i = static_cast<size_t>(y) * g.width + x;
        if (ctx.receivers[i] != kActive) continue;
        const DVec3 p(g.shadow_origin(i)), n(g.geo_normal[i]);
        if (!look.setup(p, n)) continue;
        const double z = look.depth();
        // The edge depth test uses shadow_map's bias (constant + slope-scaled).
        const DVec3 to_light = glm::normalize(map.proj.eye - p);
        const double cos_t = std::clamp(std::abs(glm::dot(n, to_light)), 1e-3, 1.0);
        const double tan_t = std::min(std::sqrt(1.0 - cos_t * cos_t) / cos_t, 100.0);
        const double bias = map_.bias + map_.slope_bias * map.texel_tan * z * tan_t;
        auto sample = [&](double sx, double sy, double& width) {
          if (radius == 0.0) {
            // Hard mode: the shadow boundary is where the depth tests of the four texels the
            // bilinear filter reads disagree; elsewhere the plain shadow map shades (§2.2: "shadow
            // mapping is used to shade non boundary parts of shadow"). This keeps an overlapping,
            // nearer silhouette from lighting the inside of another occluder's shadow.
            const int x0 = static_cast<int>(std::floor(sx - 0.5));
            const int y0 = static_cast<int>(std::floor(sy - 0.5));
            const int nb = look.blocked(x0, y0) + look.blocked(x0 + 1, y0) +
                           look.blocked(x0, y0 + 1) + look.blocked(x0 + 1, y0 + 1);
            if (nb == 0 || nb == 4) {
              width = 0.0;
              return nb == 0 ? 1.0 : 0.0;
            }
          }
          const bool occluded =
              look.blocked(static_cast<int>(std::floor(sx)), static_cast<int>(std::floor(sy)));
          const double ze = edge_depth(sx, sy);
          const bool edge_front = ze < z - bias;
          // §2.2.1: second coordinate = edge/point depth ratio scaled by the light radius:
          // penumbra width (texels) = 2R·(1/z_E − 1/z)/texel_tan = (2R/(z·texel_tan))·(z/z_E − 1).
          width = edge_front && radius > 0.0 ? 2.0 * radius / (z * map.texel_tan) * (z / ze - 1.0)
                                             : 0.0;
          const double c = table.coord(edge_distance(sx, sy), occluded, edge_front);
          return table.lookup(c, 0.5 * width);
        };
        double width = 0.0;
        double v = sample(look.sx(), look.sy(), width);
        if (radius > 0.0 && width > 0.0) {
          // §2.2.1: three more samples around the point; four on a circle of radius width/4.
          const double rr = std::min(0.25 * width, hb);
          double sum = 0.0, w_unused = 0.0;
          for (int k = 0; k < 4; ++k) {
            const double a = kPi * (0.25 + 0.5 * k);
            sum += sample(look.sx() + rr * std::cos(a), look.sy() + rr * std::sin(a), w_unused);
          }
          v = 0.25 * sum;
        }
        vis.lit[i] = static_cast<float>(std::clamp(v, 0.0, 1.0));
      }
    });
    vis.times.add("lookup", elapsed_ms(start));
    vis.counters["tam_faces"] = static_cast<double>(tam.size());
    vis.counters["silhouette_faces"] = static_cast<double>(layer.silhouette_faces);
    vis.counters["corrected_faces"] = static_cast<double>(layer.corrected_faces);
    vis.counters["silhouette_texels"] = static_cast<double>(layer.texels_visited);
    vis.counters["duplicate_faces"] = static_cast<double>(layer.duplicate_faces);
    vis.counters["half_band_texels"] = half_band;
    vis.counters["map_texel_tan"] = map.texel_tan;
    return vis;
  }

 private:
  DepthMapSettings map_;
  bool soft_;
  double width_, aa_, offset_, max_band_;
};

}  // namespace

MethodInfo silhouette_map_info() {
  MethodInfo info;
  info.name = "silhouette_map";
  info.summary =
      "shadow map + silhouette layer (signed edge distance, edge depth) from a topology-aware "
      "mesh: anti-aliased hard shadows (eq. 4) or 4-sample soft shadows of a small sphere; "
      "alpha-textured (perforated) occluders count as opaque";
  info.reference = "[Valient 2005 §2, eqs. 1, 2, 4, §2.2.1]";
  info.options = depth_map_option_specs();
  info.options.insert(
      info.options.end(),
      {
          {"mode",
           OptionType::choice,
           "hard",
           "hard: 1D table, light centre (§2.2); soft: 4 samples, 2D table (§2.2.1)",
           {"hard", "soft"}},
          {"width",
           OptionType::real,
           "3",
           "expected silhouette width, texels (thick silhouette = ±width/2)",
           {},
           1,
           256},
          {"aa_width",
           OptionType::real,
           "1",
           "width of the anti-aliasing ramp of the gradient table, texels (0 = step)",
           {},
           0,
           64},
          {"offset",
           OptionType::real,
           "0",
           "shadow-boundary offset in the table, texels (> 0 moves the edge outward)",
           {},
           -64,
           64},
          {"max_band",
           OptionType::real,
           "32",
           "soft mode: cap on the thick-silhouette half-width, texels",
           {},
           1,
           1024},
      });
  info.create = [](const MethodOptions& o) { return std::make_unique<SilhouetteMap>(o); };
  return info;
}

}  // namespace penumbra::silmap

namespace penumbra {

void register_silhouette_map(MethodRegistry& registry) {
  registry.add(silmap::silhouette_map_info());
}

}  // namespace penumbra
