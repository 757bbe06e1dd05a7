#version 460
// GEARS step 4 [seed 004 §4.2]: per pixel, every triangle of its cell rasterized onto the k×k
// light-sample bitmask by its edge planes, one 32-bit word per row (k ≤ 32). The arithmetic is the
// CPU rasterizer's (shadows/gears/raster.cpp), operation for operation and without contraction
// (`precise`), so both agree on every sample that is not within rounding of an edge.
//
// Seen from pixel point P, triangle ABC blocks light point X(u, v) = P + w + u·eu + v·ev iff X is
// on the positive side of the edge planes (P, A, B), (P, B, C), (P, C, A), oriented by
// s = sign(det(A−P, B−P, C−P)), and beyond the triangle's plane; each test is a line in light uv,
// so no clipping is needed.
#include "common.glsl"

layout(push_constant) uniform Push {
  Vec4s pix;   // per active pixel: p, w, eu, ev
  Vec4s tris;  // 3 per triangle
  Uints cell;  // per active pixel (~0: other side)
  Uints begin;
  Uints end;
  Uints vals;       // sorted triangle ids
  Uints rows_out;   // k words per active pixel
  Uints emit_rows;  // k words: the samples the light emits from
  uint n;
  int k;
  vec2 uv_lo;  // bounding box of the sample positions
  vec2 uv_hi;
} pc;

// max/min as the CPU's vector code writes them (a NaN operand picks b).
float vmax(float a, float b) { return a > b ? a : b; }
float vmin(float a, float b) { return a < b ? a : b; }

void main() {
  const uint a = global_id();
  if (a >= pc.n) return;
  const uint c = pc.cell.v[a];
  if (c == 0xffffffffu) return;
  const int k = pc.k;
  const float kf = float(k);
  const vec3 p = pc.pix.v[4u * a].xyz;
  const vec3 w = pc.pix.v[4u * a + 1u].xyz;
  const vec3 eu = pc.pix.v[4u * a + 2u].xyz;
  const vec3 ev = pc.pix.v[4u * a + 3u].xyz;
  uint rows[32];
  uint emit[32];
  for (int j = 0; j < 32; ++j) {
    rows[j] = 0u;
    emit[j] = j < k ? pc.emit_rows.v[j] : 0u;
  }
  const uint e0 = pc.begin.v[c], e1 = pc.end.v[c];
  for (uint e = e0; e < e1; ++e) {
    const uint t = pc.vals.v[e];
    precise vec3 A = pc.tris.v[3u * t].xyz - p;
    precise vec3 B = pc.tris.v[3u * t + 1u].xyz - p;
    precise vec3 C = pc.tris.v[3u * t + 2u].xyz - p;
    // Edge-plane normals n0 = a×b, n1 = b×c, n2 = c×a.
    precise vec3 n[3];
    n[0] = vec3(A.y * B.z - A.z * B.y, A.z * B.x - A.x * B.z, A.x * B.y - A.y * B.x);
    n[1] = vec3(B.y * C.z - B.z * C.y, B.z * C.x - B.x * C.z, B.x * C.y - B.y * C.x);
    n[2] = vec3(C.y * A.z - C.z * A.y, C.z * A.x - C.x * A.z, C.x * A.y - C.y * A.x);
    precise float det = A.x * n[1].x + A.y * n[1].y + A.z * n[1].z;
    if (det == 0.0) continue;
    const float s = det > 0.0 ? 1.0 : -1.0;
    precise float la[4], lb[4], lc[4];
    for (int m = 0; m < 3; ++m) {
      la[m] = s * (n[m].x * w.x + n[m].y * w.y + n[m].z * w.z);
      lb[m] = s * (n[m].x * eu.x + n[m].y * eu.y + n[m].z * eu.z);
      lc[m] = s * (n[m].x * ev.x + n[m].y * ev.y + n[m].z * ev.z);
    }
    // The plane: the segment reaches the triangle (t ≤ 1) iff Σ s·e_i(X) ≥ |det|.
    la[3] = la[0] + la[1] + la[2] - s * det;
    lb[3] = lb[0] + lb[1] + lb[2];
    lc[3] = lc[0] + lc[1] + lc[2];
    bool ok = true;
    for (int m = 0; m < 4; ++m) {
      precise float best = la[m] + vmax(lb[m] * pc.uv_lo.x, lb[m] * pc.uv_hi.x) +
                           vmax(lc[m] * pc.uv_lo.y, lc[m] * pc.uv_hi.y);
      ok = ok && best >= 0.0;
    }
    if (!ok) continue;
    // Row-span form in sample-index space (sample (i, j) at ((i + ½)/k, (j + ½)/k)): line m is
    // al + b·i + c·j ≥ 0, a lower bound on i (b > 0) or an upper bound (b < 0).
    const float inf = uintBitsToFloat(0x7f800000u);
    precise float al[4], inv[4], lo_off[4], hi_off[4];
    bool flat_line = false;
    for (int m = 0; m < 4; ++m) {
      al[m] = kf * la[m] + 0.5 * (lb[m] + lc[m]);
      inv[m] = lb[m] != 0.0 ? -1.0 / lb[m] : 0.0;
      lo_off[m] = lb[m] > 0.0 ? 0.0 : -inf;
      hi_off[m] = lb[m] < 0.0 ? 0.0 : inf;
      flat_line = flat_line || lb[m] == 0.0;
    }
    for (int j = 0; j < k; ++j) {
      const float jf = float(j);
      precise float t_lo = -2.0, t_hi = kf + 1.0;
      bool empty = false;
      for (int m = 0; m < 4; ++m) {
        precise float cj = al[m] + lc[m] * jf;
        precise float tm = cj * inv[m];
        t_lo = vmax(t_lo, tm + lo_off[m]);
        t_hi = vmin(t_hi, tm + hi_off[m]);
        if (flat_line && lb[m] == 0.0) empty = empty || cj < 0.0;
      }
      const int lo = max(int(ceil(vmin(t_lo, kf + 1.0))), 0);
      const int hi = min(int(floor(vmax(t_hi, -2.0))), k - 1);
      if (empty || lo > hi) continue;
      rows[j] |= (2u << uint(hi)) - (1u << uint(lo));
    }
    bool full = true;
    for (int j = 0; j < k; ++j) full = full && (rows[j] & emit[j]) == emit[j];
    if (full) break;  // every emitting sample blocked: no later triangle can change the mask
  }
  for (int j = 0; j < k; ++j) pc.rows_out.v[a * uint(k) + uint(j)] = rows[j] & emit[j];
}
