#version 460
// `silhouette_map`'s silhouette pass [Valient 2005 §2.1.1] as a gather: one thread per texel walks
// the faces binned to its 16×16 tile in face order, so every texel merges its candidates in the
// order the CPU's render_silhouettes does — the LESSEQUAL merge with its 1 % depth tolerance is not
// order-free, so a scatter with atomics could not reproduce it. Per face the texel must lie in the
// CPU rasterizer's cover of the scaled triangle (edge functions and top-left rule, set up on the
// host) and in the silhouette edges' spans; then the signed distance to the nearest silhouette
// edge and that point's depth, in double, operation for operation as on the CPU (`precise`: no
// contraction into FMAs the CPU does not do; hypot as glibc's correction step computes it).
// One workgroup per tile that has faces; dispatched in chunks of bin entries (llvmpipe stops a
// loop after 65535 iterations). Texels off every silhouette keep depth +inf: the lookup derives
// their distance from the depth map's coverage (±half_band), as the CPU's fill does.
#extension GL_EXT_shader_explicit_arithmetic_types_float64 : require
#include "common.glsl"

struct Face {
  double sx[3], sy[3], sz[3];  // projected face: x, y texels, z = 1/w
  double side[3];              // sign of the face's side of each edge line
  double ux[3], uy[3], len[3];  // silhouette edges: unit direction and length (host's hypot)
  double bx[3], by[3], ex[3], ey[3], sgn[3];  // the scaled cover's oriented edge functions
  int x_lo, x_hi, y_lo, y_hi;  // the cover's texel box cut to its silhouette edges' reach
  uint mask;    // bit c: edge c → c+1 is a silhouette
  uint owns;    // bit i: edge i owns the centres on it (top-left rule)
  uint orient;  // 1: edge_fn(s0, s1, s2) ≥ 0
  uint pad;
};

layout(buffer_reference, scalar) buffer Faces { Face v[]; };

layout(push_constant) uniform Push {
  Faces faces;
  Uints tiles;      // the tiles with faces (index = ty · tiles_x + tx), one workgroup each
  Uints bin_begin;  // per listed tile: first entry; listed tiles + 1 entries
  Uints bin_faces;  // face indices, per tile in face order
  Floats distance;  // the layer: signed edge distance, texels (0 before the first chunk)
  Floats depth;     // the layer: edge depth (+inf: none, before the first chunk)
  Uints visited;    // texels evaluated (the CPU's texels_visited)
  double half_band;
  double span_radius;  // half_band + 1
  uint res, tiles_x, tile_count, first, chunk;
} pc;

const uint kTile = 16u;
Faces F;  // pc.faces: fields are read one by one where used

double edge_fn(double ax, double ay, double bx, double by, double x, double y) {
  precise const double e = (bx - ax) * (y - ay) - (by - ay) * (x - ax);
  return e;
}

/// glibc's hypot (its correction of sqrt(x² + y²), for operands of moderate size).
double hypot_glibc(double x, double y) {
  const double ax = max(abs(x), abs(y)), ay = min(abs(x), abs(y));
  if (ay <= ax * 5.551115123125783e-17lf) return ax + ay;
  precise double h = sqrt(ax * ax + ay * ay);
  precise double t1, t2;
  if (h <= 2.0 * ay) {
    precise const double delta = h - ay;
    t1 = ax * (2.0 * delta - ax);
    t2 = (delta - 2.0 * (ax - ay)) * delta;
  } else {
    precise const double delta = h - ax;
    t1 = 2.0 * delta * (ax - 2.0 * ay);
    t2 = (4.0 * delta - ay) * ay + delta * delta;
  }
  h -= (t1 + t2) / (2.0 * h);
  return h;
}

/// lower ≤ k·x + m ≤ upper as an x range, intersected into [x0, x1] (silhouette_spans' clip).
void clip(double k, double m, double lower, double upper, inout double x0, inout double x1) {
  if (abs(k) < 1e-12) {
    if (m < lower || m > upper) x1 = x0 - 1.0;
    return;
  }
  precise const double u = (lower - m) / k;
  precise const double v = (upper - m) / k;
  x0 = max(x0, min(u, v));
  x1 = min(x1, max(u, v));
}

/// Is column x within the span of silhouette edge c on the row through py (silhouette_spans)?
bool in_span(uint fi, int c, double py, int x) {
  const double r = pc.span_radius;
  double x0 = -1.0, x1 = double(pc.res) + 1.0;
  const double ax = F.v[fi].sx[c], ay = F.v[fi].sy[c], len = F.v[fi].len[c];
  if (len < 1e-12) {
    clip(1.0, -ax, -r, r, x0, x1);
    clip(0.0, py - ay, -r, r, x0, x1);
  } else {
    const double ux = F.v[fi].ux[c], uy = F.v[fi].uy[c];
    precise const double m0 = (py - ay) * uy - ax * ux;
    precise const double m1 = (py - ay) * ux + ax * uy;
    precise const double up0 = len + r;
    clip(ux, m0, -r, up0, x0, x1);  // along the edge
    clip(-uy, m1, -r, r, x0, x1);   // across it
  }
  if (!(x0 <= x1)) return false;
  precise const double lo = ceil(x0 - 0.5), hi = floor(x1 - 0.5);
  return double(x) >= lo && double(x) <= hi;
}

/// rasterize_triangle_spans' coverage of the texel centre (px, py) by the scaled cover.
bool covers(uint fi, double px, double py) {
  const uint owns = F.v[fi].owns;
  for (int i = 0; i < 3; ++i) {
    precise const double w =
        F.v[fi].sgn[i] * (F.v[fi].ex[i] * (py - F.v[fi].by[i]) - F.v[fi].ey[i] * (px - F.v[fi].bx[i]));
    if (!(w > 0.0 || (w == 0.0 && (owns & (1u << i)) != 0u))) return false;
  }
  return true;
}

bool inside_face(uint fi, double px, double py) {
  const double o = F.v[fi].orient != 0u ? 1.0 : -1.0;
  for (int c = 0; c < 3; ++c) {
    const int n = (c + 1) % 3;
    precise const double e =
        o * edge_fn(F.v[fi].sx[c], F.v[fi].sy[c], F.v[fi].sx[n], F.v[fi].sy[n], px, py);
    if (e < 0.0) return false;
  }
  return true;
}

void main() {
  const uint res = pc.res;
  const uint slot = group_id(), local = gl_LocalInvocationIndex;
  if (slot >= pc.tile_count) return;
  F = pc.faces;
  const uint tile = pc.tiles.v[slot];
  const uint tx = tile % pc.tiles_x, ty = tile / pc.tiles_x;
  const int x = int(tx * kTile + local % kTile), y = int(ty * kTile + local / kTile);
  if (x >= int(res) || y >= int(res)) return;
  const uint texel = uint(y) * res + uint(x);
  float zd = pc.depth.v[texel], dd = pc.distance.v[texel];
  const uint begin = pc.bin_begin.v[slot], end = pc.bin_begin.v[slot + 1u];
  const uint from = begin + min(pc.first, end - begin);
  const uint to = from + min(pc.chunk, end - from);
  if (from >= to) return;
  const double qx = double(x) + 0.5, qy = double(y) + 0.5;
  uint visited = 0u;
  for (uint e = from; e < to; ++e) {
    const uint fi = pc.bin_faces.v[e];
    if (x < F.v[fi].x_lo || x > F.v[fi].x_hi || y < F.v[fi].y_lo || y > F.v[fi].y_hi) continue;
    const uint mask = F.v[fi].mask;
    bool spanned = false;
    for (int c = 0; c < 3 && !spanned; ++c)
      spanned = (mask & (1u << c)) != 0u && in_span(fi, c, qy, x);
    if (!spanned || !covers(fi, qx, qy)) continue;
    ++visited;
    double best = uintBitsToFloat(0x7f800000u), best_inv_w = 0.0;
    bool inside = false;
    for (int c = 0; c < 3; ++c) {
      if ((mask & (1u << c)) == 0u) continue;
      const int n = (c + 1) % 3;
      const double ax = F.v[fi].sx[c], ay = F.v[fi].sy[c];
      precise const double ex = F.v[fi].sx[n] - ax, ey = F.v[fi].sy[n] - ay;
      precise const double len2 = ex * ex + ey * ey;
      precise const double tn = ((qx - ax) * ex + (qy - ay) * ey) / len2;
      const double tc = len2 > 0.0 ? clamp(tn, 0.0, 1.0) : 0.0;
      precise const double dx = qx - ax - tc * ex, dy = qy - ay - tc * ey;
      const double dist = hypot_glibc(dx, dy);
      if (dist < best) {
        best = dist;
        precise const double iw = F.v[fi].sz[c] + tc * (F.v[fi].sz[n] - F.v[fi].sz[c]);
        best_inv_w = iw;
        inside = tc > 0.0 && tc < 1.0
                     ? F.v[fi].side[c] * edge_fn(ax, ay, F.v[fi].sx[n], F.v[fi].sy[n], qx, qy) >= 0.0
                     : inside_face(fi, qx, qy);
      }
    }
    if (!(best <= pc.half_band) || !(best_inv_w > 0.0)) continue;
    precise const float depth = float(1.0 / best_inv_w);
    const float d = float(inside ? best : -best);
    // LESSEQUAL depth and distance tests (§2.1.1), in float as on the CPU.
    precise const float tol = 0.01 * depth;
    precise const float lo = zd - tol, hi = zd + tol;
    if (depth < lo || (depth <= hi && abs(d) < abs(dd))) {
      zd = depth;
      dd = d;
    }
  }
  pc.depth.v[texel] = zd;
  pc.distance.v[texel] = dd;
  if (visited != 0u) atomicAdd(pc.visited.v[0], visited);
}
