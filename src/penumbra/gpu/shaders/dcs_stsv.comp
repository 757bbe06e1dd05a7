#version 460
// dcs step 2b, soft textured shadow volumes [Forest 2008 §5.1.3–5.1.4, §5.2.2]: per active pixel,
// the S-triangles [first, first + chunk) of its tile's bin whose volume holds it; for each, J (eq.
// 5.9 composed with the light's uv frame, stsv_lookup.hpp make_pair, in double) and, per sample of
// its band range, the crossing test and the alpha texel at the crossing's barycentrics
// (blocked_samples, in float): +1 on the counter of the triangle's class where the texel is
// opaque. Records in state[2a] that the pixel had a pair (no longer uniform).
#include "common.glsl"
#include "dcs.glsl"

/// stsv.hpp STriangle: vertices, M' by rows, uvs, its alpha texture (offset into the texel bits,
/// size), its counter class, and how many volume sides (2t, 2t + 1 in the wedge buffer) it has.
struct STri {
  dvec3 v0, e1, e2;
  dvec3 to_triangle[3];
  vec2 uv[3];
  uint texel_offset;
  int width, height;
  uint layer_class;
  int side_count, pad;
};
layout(buffer_reference, scalar) buffer STris { STri v[]; };

layout(push_constant) uniform Push {
  Pixels pix;
  STris tris;
  Wedges sides;
  Uints bin_begin;    // per tile, + 1
  Uints bin_entries;  // S-triangle indices
  Uints texels;       // 1 where alpha ≥ the cutoff
  Vec2s samples;      // sorted by band
  Ints band_begin;
  Ints counters;
  Ints state;
  uint na, n, k, first, chunk;
  float min_inverse_t;  // stsv_lookup.hpp kMinInverseT
  uint sample_stride, band_stride;  // 0, or n and k + 1: each pixel's own samples
} pc;

bool side_contains(uint w, dvec3 p) {
  const int count = pc.sides.v[w].plane_count;
  const double tol = pc.sides.v[w].tolerance;
  for (int i = 0; i < count; ++i) {
    const dvec4 plane = pc.sides.v[w].planes[i];
    precise const double lhs = dot3(plane.xyz, p);
    precise const double rhs = plane.w - tol;
    if (lhs < rhs) return false;
  }
  return true;
}

precise dvec3 to_triangle(uint t, dvec3 x) {
  return dvec3(dot3(pc.tris.v[t].to_triangle[0], x), dot3(pc.tris.v[t].to_triangle[1], x),
               dot3(pc.tris.v[t].to_triangle[2], x));
}

/// make_pair's row r of W·M' for M'·(s − p) = g.
float pair_row(dvec3 g, dvec3 g0, int r) {
  precise double x;
  if (r == 0)
    x = g.x - g0.x * g.z / g0.z;
  else if (r == 1)
    x = g.y - g0.y * g.z / g0.z;
  else
    x = g.z / g0.z;
  return float(x);
}

void main() {
  const uint a = global_id();
  if (a >= pc.na) return;
  const uint tile = pc.pix.v[a].tile, flags = pc.pix.v[a].flags;
  const uint b1 = pc.bin_begin.v[tile + 1u];
  const uint from = pc.bin_begin.v[tile] + pc.first;
  if (from >= b1) return;
  const uint to = min(b1, from + pc.chunk);
  const dvec3 p = pc.pix.v[a].p;
  bool any_pair = false;
  for (uint j = from; j < to; ++j) {
    const uint t = pc.bin_entries.v[j];
    const int side_count = pc.tris.v[t].side_count;
    bool inside = false;
    for (int sd = 0; sd < side_count && !inside; ++sd) inside = side_contains(2u * t + uint(sd), p);
    if (!inside) continue;
    const dvec3 v0 = pc.tris.v[t].v0;
    double v_lo = 0.0, v_hi = 1.0;
    if ((flags & kValid) != 0u) {
      // The triangle's projection from p onto the light bounds the samples it can block.
      const dvec3 to_u = pc.pix.v[a].to_u, to_v = pc.pix.v[a].to_v, to_w = pc.pix.v[a].to_w;
      precise const dvec3 q0 = v0, q1 = v0 + pc.tris.v[t].e1, q2 = v0 + pc.tris.v[t].e2;
      dvec3 h[3];
      for (int c = 0; c < 3; ++c) {
        precise const dvec3 d = (c == 0 ? q0 : c == 1 ? q1 : q2) - p;
        h[c] = dvec3(dot3(d, to_u), dot3(d, to_v), dot3(d, to_w));
      }
      if (h[0].z > 1.0 && h[1].z > 1.0 && h[2].z > 1.0) continue;
      if (h[0].z > 0.0 && h[1].z > 0.0 && h[2].z > 0.0) {
        double u0 = 1.0 / 0.0, u1 = -1.0 / 0.0, w0 = 1.0 / 0.0, w1 = -1.0 / 0.0;
        for (int c = 0; c < 3; ++c) {
          precise const double x = h[c].x / h[c].z, y = h[c].y / h[c].z;
          u0 = min(u0, x), u1 = max(u1, x);
          w0 = min(w0, y), w1 = max(w1, y);
        }
        const double m = 1e-6;
        if (u1 < -m || u0 > 1.0 + m || w1 < -m || w0 > 1.0 + m) continue;
        v_lo = w0, v_hi = w1;
      }
    }
    precise const dvec3 g0 = to_triangle(t, v0 - p);
    if (!(g0.z != 0.0)) continue;  // p in the plane
    precise const dvec3 cp = pc.pix.v[a].corner - p;
    const dvec3 gu = to_triangle(t, pc.pix.v[a].edge_u), gv = to_triangle(t, pc.pix.v[a].edge_v),
                gc = to_triangle(t, cp);
    vec3 ja, jb, jc;
    for (int r = 0; r < 3; ++r) {
      ja[r] = pair_row(gu, g0, r);
      jb[r] = pair_row(gv, g0, r);
      jc[r] = pair_row(gc, g0, r);
    }
    any_pair = true;
    int first, last;
    band_range(pc.band_begin, a * pc.band_stride, int(pc.k), v_lo, v_hi, first, last);
    const vec2 uv0 = pc.tris.v[t].uv[0], uv1 = pc.tris.v[t].uv[1], uv2 = pc.tris.v[t].uv[2];
    const uint offset = pc.tris.v[t].texel_offset;
    const int width = pc.tris.v[t].width, height = pc.tris.v[t].height;
    const uint base = pc.tris.v[t].layer_class * pc.n;
    for (int s = first; s < last; ++s) {
      const vec2 su = pc.samples.v[a * pc.sample_stride + uint(s)];
      precise const float hx = ja.x * su.x + jb.x * su.y + jc.x;
      precise const float hy = ja.y * su.x + jb.y * su.y + jc.y;
      precise const float hz = ja.z * su.x + jb.z * su.y + jc.z;
      precise const float rest = hz - hx - hy;
      if (!(hx >= 0.0 && hy >= 0.0 && rest >= 0.0 && hz >= pc.min_inverse_t)) continue;
      // 1/hz correctly rounded (a float division may be 2.5 ulp in Vulkan; the double quotient
      // rounded once to float is the IEEE float quotient).
      const float inv = float(1.0 / double(hz));
      precise const float bu = hx * inv, bv = hy * inv;
      precise const float w0 = 1.0 - bu - bv;
      precise const vec2 uv = w0 * uv0 + bu * uv1 + bv * uv2;
      // Texture::texel_index.
      precise const float fu = uv.x - floor(uv.x), fv = uv.y - floor(uv.y);
      const int tx = min(width - 1, max(0, int(fu * float(width))));
      const int ty = min(height - 1, max(0, int(fv * float(height))));
      if (pc.texels.v[offset + uint(ty * width + tx)] != 0u)
        pc.counters.v[(base + uint(s)) * pc.na + a] += 1;
    }
  }
  if (any_pair) pc.state.v[2u * a] = 1;
}
