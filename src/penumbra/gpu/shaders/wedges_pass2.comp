#version 460
// `wedges` pass 2 [Assarsson 2003 III §3.2, IV §4.2; Forest 2008 Algorithm 3]: per active pixel,
// the wedges [first, first + chunk) of its tile's bin that hold it, each edge projected from the
// pixel and clipped to the light, its signed coverage — area(square ∩ sector) − area(triangle)
// (coverage.cpp box_sector), or the disk's sector minus triangle — added to the pixel's sum
// (initially its layered hard count), in bin order, in double: the CPU's sum. The last chunk
// writes V = 1 − clamp(sum, 0, 1).
#include "common.glsl"
#include "dcs.glsl"

layout(buffer_reference, scalar) buffer Doubles { double v[]; };

/// One active pixel: its shadow origin, light projection, 1/uv area of its light frame, tile, flags
/// (dcs.glsl kValid, kRound, kTauNeg).
struct WedgePixel {
  dvec3 p, to_u, to_v, to_w;
  double inv_area;
  uint tile, flags;
};
layout(buffer_reference, scalar) buffer WedgePixels { WedgePixel v[]; };

layout(push_constant) uniform Push {
  WedgePixels pix;
  Wedges wedges;
  Doubles weight;  // per wedge: multiplicity / layers
  Uints bin_begin;
  Uints bin_entries;
  Doubles sum;  // per pixel, initially the layered hard count
  Floats lit;
  uint na, first, chunk, last;  // last: this dispatch writes V
} pc;

bool contains(uint w, dvec3 p) {
  const int count = pc.wedges.v[w].plane_count;
  const double tol = pc.wedges.v[w].tolerance;
  for (int i = 0; i < count; ++i) {
    const dvec4 plane = pc.wedges.v[w].planes[i];
    precise const double lhs = dot3(plane.xyz, p);
    precise const double rhs = plane.w - tol;
    if (lhs < rhs) return false;
  }
  return true;
}

/// coverage.cpp box_sector(0, 1, a, b).minus_triangle().
double square_sector_minus_triangle(dvec2 a, dvec2 b) {
  const dvec2 c = dvec2(0.5);
  precise const dvec2 da = a - c, db = b - c;
  const double tri2 = cross2(da, db);
  if (tri2 == 0.0) return 0.0;
  const double s = tri2 > 0.0 ? 1.0 : -1.0;
  dvec2 outline[4];
  int n = 0;
  for (int e = 0; e < 2; ++e) {  // where the rays c + λ·da and c + λ·db leave the square
    if (e == 1) {
      // Corners strictly inside the sector (at most two), in angular order.
      dvec2 corners[2];
      int m = 0;
      for (int k = 0; k < 4; ++k) {
        const dvec2 q = dvec2(k == 1 || k == 2 ? 1.0 : 0.0, k >= 2 ? 1.0 : 0.0);
        precise const dvec2 dk = q - c;
        precise const double s0 = s * cross2(da, dk), s1 = s * cross2(dk, db);
        if (m < 2 && s0 > 0.0 && s1 > 0.0) corners[m++] = q;
      }
      if (m == 2) {
        precise const double turn = s * cross2(corners[0] - c, corners[1] - c);
        if (turn < 0.0) {
          const dvec2 t = corners[0];
          corners[0] = corners[1];
          corners[1] = t;
        }
      }
      for (int i = 0; i < m; ++i) outline[n++] = corners[i];
    }
    const dvec2 d = e == 0 ? da : db;
    double lambda = 1.0 / 0.0;
    for (int k = 0; k < 2; ++k) {
      if (d[k] > 0.0) {
        precise const double l = (1.0 - c[k]) / d[k];
        lambda = min(lambda, l);
      }
      if (d[k] < 0.0) {
        precise const double l = (0.0 - c[k]) / d[k];
        lambda = min(lambda, l);
      }
    }
    precise const dvec2 x = c + lambda * d;
    outline[n++] = x;
  }
  precise double area2 = 0.0;
  for (int i = 0; i + 1 < n; ++i) area2 += s * cross2(outline[i] - c, outline[i + 1] - c);
  precise const double r = (tri2 > 0.0 ? 0.5 : -0.5) * (area2 - abs(tri2));
  return r;
}

/// coverage.cpp disk_sector_minus_triangle. GLSL has no double atan2: the angle is the float
/// atan's (|error| ≲ 1e-7 rad, ≲ 1e-8 of the light's area per edge).
double disk_sector_minus_triangle(dvec2 a, dvec2 b) {
  precise const dvec2 da = a - dvec2(0.5), db = b - dvec2(0.5);
  const double cr = cross2(da, db);
  precise const double dt = da.x * db.x + da.y * db.y;
  const double angle = double(atan(float(cr), float(dt)));
  precise const double r = 0.5 * (0.25 * angle - cr);
  return r;
}

void main() {
  const uint a = global_id();
  if (a >= pc.na) return;
  const uint flags = pc.pix.v[a].flags;
  precise double sum = pc.sum.v[a];
  if ((flags & kValid) != 0u) {
    const uint tile = pc.pix.v[a].tile;
    const uint b1 = pc.bin_begin.v[tile + 1u];
    const uint from = pc.bin_begin.v[tile] + pc.first;
    const uint to = min(b1, from + pc.chunk);
    const dvec3 p = pc.pix.v[a].p;
    const dvec3 to_u = pc.pix.v[a].to_u, to_v = pc.pix.v[a].to_v, to_w = pc.pix.v[a].to_w;
    const double tau = (flags & kTauNeg) != 0u ? -1.0 : 1.0;
    const double inv_area = pc.pix.v[a].inv_area;
    for (uint j = from; j < to; ++j) {
      const uint w = pc.bin_entries.v[j];
      if (!contains(w, p)) continue;
      precise const dvec3 d0 = pc.wedges.v[w].e0 - p, d1 = pc.wedges.v[w].e1 - p;
      const dvec3 A = dvec3(dot3(d0, to_u), dot3(d0, to_v), dot3(d0, to_w));
      const dvec3 B = dvec3(dot3(d1, to_u), dot3(d1, to_v), dot3(d1, to_w));
      dvec2 ua, ub;
      if (!clip_square(A, B, ua, ub)) continue;
      const bool round = (flags & kRound) != 0u;
      if (round && !clip_disk(ua, ub)) continue;
      const double area =
          round ? disk_sector_minus_triangle(ua, ub) : square_sector_minus_triangle(ua, ub);
      if (area == 0.0) continue;
      // PixelLight::occlusion: −τ · weight · area / |light uv|.
      precise const double occlusion = -tau * pc.weight.v[w] * area * inv_area;
      sum += occlusion;
    }
  }
  if (pc.last != 0u)
    pc.lit.v[a] = float(1.0 - clamp(sum, 0.0, 1.0));
  else
    pc.sum.v[a] = sum;
}
