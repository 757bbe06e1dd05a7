#version 460
// GEARS step 4 [Wang 2014 §4.2]: per pixel, every triangle of its cell rasterized onto the k×k
// light-sample bitmask by its edge planes, one 32-bit word per row (k ≤ 32). The arithmetic is the
// CPU rasterizer's (shadows/gears/raster.cpp), operation for operation and without contraction
// (`precise`), so both agree on every sample that is not within rounding of an edge.
//
// Seen from pixel point P, triangle ABC blocks light point X(u, v) = P + w + u·eu + v·ev iff X is
// on the positive side of the edge planes (P, A, B), (P, B, C), (P, C, A), oriented by
// s = sign(det(A−P, B−P, C−P)), and beyond the triangle's plane; each test is a line in light uv,
// so no clipping is needed.
//
// Loops: a dispatch walks at most `chunk` triangles of a cell (the host dispatches the chunks of
// the longest cell in turn, OR-ing into rows_out): llvmpipe (lavapipe) stops any loop after 65535
// iterations in total, counting a nested loop's iterations across its enclosing loop's, so
// chunk × 32 rows × 4 lines stays below that (alpha-tested samples count too: a cell dense in alpha-tested
// triangles can still reach the limit there).
#extension GL_EXT_control_flow_attributes : require
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
  uint first;  // this dispatch: entries [first, first + chunk) of each cell's list
  uint chunk;
  vec2 uv_lo;  // bounding box of the sample positions
  vec2 uv_hi;
  Vec4s alpha;      // 3 per triangle: (texel offset, width, height, 1 = alpha-tested), uv0 uv1, uv2
  Uints texels;     // alpha textures: 1 where the texel blocks (alpha ≥ the cutoff)
  Floats samples;   // light uv of sample s at 2s, 2s + 1
} pc;

/// Does alpha-tested triangle t block sample s? The texture decides at the barycentrics of the
/// sample's ray (the CPU's hit_barycentrics and Texture::texel_index).
bool alpha_blocks(uint t, float la[4], float lb[4], float lc[4], int s) {
  const vec4 h = pc.alpha.v[3u * t];
  const vec4 uv01 = pc.alpha.v[3u * t + 1u];
  const vec2 uv2 = pc.alpha.v[3u * t + 2u].xy;
  const float su = pc.samples.v[2 * s], sv = pc.samples.v[2 * s + 1];
  precise float e0 = la[0] + lb[0] * su + lc[0] * sv;  // ∝ λ_C
  precise float e1 = la[1] + lb[1] * su + lc[1] * sv;  // ∝ λ_A
  precise float e2 = la[2] + lb[2] * su + lc[2] * sv;  // ∝ λ_B
  precise float sum = e0 + e1 + e2;
  precise float bu = sum > 0.0 ? e2 / sum : 0.0, bv = sum > 0.0 ? e0 / sum : 0.0;
  precise vec2 uv = (1.0 - bu - bv) * uv01.xy + bu * uv01.zw + bv * uv2;
  const int width = int(h.y), height = int(h.z);
  const float u = uv.x - floor(uv.x), v = uv.y - floor(uv.y);
  const int tx = min(width - 1, max(0, int(u * float(width))));
  const int ty = min(height - 1, max(0, int(v * float(height))));
  return pc.texels.v[floatBitsToUint(h.x) + uint(ty * width + tx)] != 0u;
}

// max/min as the CPU's vector code writes them (a NaN operand picks b).
float vmax(float a, float b) { return a > b ? a : b; }
float vmin(float a, float b) { return a < b ? a : b; }

/// u × w with u, w in lexicographic order; `sgn` = +1 when that order is (u, w), else −1.
vec3 edge_normal(vec3 u, vec3 w, out float sgn) {
  const bool before = u.x < w.x || (u.x == w.x && (u.y < w.y || (u.y == w.y && u.z <= w.z)));
  const vec3 p0 = before ? u : w, p1 = before ? w : u;
  sgn = before ? 1.0 : -1.0;
  precise vec3 r = vec3(p0.y * p1.z - p0.z * p1.y, p0.z * p1.x - p0.x * p1.z,
                        p0.x * p1.y - p0.y * p1.x);
  return r;
}

/// ORs triangle t's coverage of the k×k samples into rows; false when it covers nothing.
bool raster_triangle(uint t, vec3 p, vec3 w, vec3 eu, vec3 ev, int k, inout uint rows[32]) {
  const float kf = float(k);
  precise vec3 A = pc.tris.v[3u * t].xyz - p;
  precise vec3 B = pc.tris.v[3u * t + 1u].xyz - p;
  precise vec3 C = pc.tris.v[3u * t + 2u].xyz - p;
  // Edge-plane normals n0 = a×b, n1 = b×c, n2 = c×a, each from its two vertices in a canonical
  // (lexicographic) order and then signed for this triangle, so that two triangles sharing an
  // edge get exactly opposite lines (watertight, as on the CPU).
  precise vec3 n[3];
  float sgn[3];
  n[0] = edge_normal(A, B, sgn[0]);
  n[1] = edge_normal(B, C, sgn[1]);
  n[2] = edge_normal(C, A, sgn[2]);
  precise float det = sgn[1] * (A.x * n[1].x + A.y * n[1].y + A.z * n[1].z);
  if (det == 0.0) return false;
  const float s = det > 0.0 ? 1.0 : -1.0;
  precise float la[4], lb[4], lc[4];
  [[unroll]] for (int m = 0; m < 3; ++m) {
    const float sm = s * sgn[m];
    la[m] = sm * (n[m].x * w.x + n[m].y * w.y + n[m].z * w.z);
    lb[m] = sm * (n[m].x * eu.x + n[m].y * eu.y + n[m].z * eu.z);
    lc[m] = sm * (n[m].x * ev.x + n[m].y * ev.y + n[m].z * ev.z);
  }
  // The plane: the segment reaches the triangle (t ≤ 1) iff Σ s·e_i(X) ≥ |det|.
  la[3] = la[0] + la[1] + la[2] - s * det;
  lb[3] = lb[0] + lb[1] + lb[2];
  lc[3] = lc[0] + lc[1] + lc[2];
  // Can every line be non-negative somewhere in the samples' bounding box?
  [[unroll]] for (int m = 0; m < 4; ++m) {
    precise float best = la[m] + vmax(lb[m] * pc.uv_lo.x, lb[m] * pc.uv_hi.x) +
                         vmax(lc[m] * pc.uv_lo.y, lc[m] * pc.uv_hi.y);
    if (!(best >= 0.0)) return false;
  }
  // Row-span form in sample-index space (sample (i, j) at ((i + ½)/k, (j + ½)/k)): line m is
  // al + b·i + c·j ≥ 0, a lower bound on i (b > 0) or an upper bound (b < 0).
  const float inf = uintBitsToFloat(0x7f800000u);
  precise float al[4], inv[4], lo_off[4], hi_off[4];
  bool flat_line = false;
  [[unroll]] for (int m = 0; m < 4; ++m) {
    al[m] = kf * la[m] + 0.5 * (lb[m] + lc[m]);
    inv[m] = lb[m] != 0.0 ? -1.0 / lb[m] : 0.0;
    lo_off[m] = lb[m] > 0.0 ? 0.0 : -inf;
    hi_off[m] = lb[m] < 0.0 ? 0.0 : inf;
    flat_line = flat_line || lb[m] == 0.0;
  }
  bool any = false;
  const bool alpha_tested = pc.alpha.v[3u * t].w != 0.0;
  for (int j = 0; j < k; ++j) {
    const float jf = float(j);
    precise float t_lo = -2.0, t_hi = kf + 1.0;
    bool empty = false;
    [[unroll]] for (int m = 0; m < 4; ++m) {
      precise float cj = al[m] + lc[m] * jf;
      precise float tm = cj * inv[m];
      t_lo = vmax(t_lo, tm + lo_off[m]);
      t_hi = vmin(t_hi, tm + hi_off[m]);
      if (flat_line && lb[m] == 0.0) empty = empty || cj < 0.0;
    }
    const int lo = max(int(ceil(vmin(t_lo, kf + 1.0))), 0);
    const int hi = min(int(floor(vmax(t_hi, -2.0))), k - 1);
    if (!empty && lo <= hi) {
      uint span = (2u << uint(hi)) - (1u << uint(lo));
      if (alpha_tested)
        for (int i = lo; i <= hi; ++i)
          if (!alpha_blocks(t, la, lb, lc, j * k + i)) span &= ~(1u << uint(i));
      rows[j] |= span;
      any = any || span != 0u;
    }
  }
  return any;
}

void main() {
  const uint a = global_id();
  if (a >= pc.n) return;
  const uint c = pc.cell.v[a];
  if (c == 0xffffffffu) return;
  const int k = pc.k;
  const vec3 p = pc.pix.v[4u * a].xyz;
  const vec3 w = pc.pix.v[4u * a + 1u].xyz;
  const vec3 eu = pc.pix.v[4u * a + 2u].xyz;
  const vec3 ev = pc.pix.v[4u * a + 3u].xyz;
  const uint e0 = pc.begin.v[c] + pc.first, e1 = min(pc.end.v[c], e0 + pc.chunk);
  if (e0 >= e1) return;
  const uint base = a * uint(k);
  uint rows[32];
  uint emit[32];
  bool full = true;
  for (int j = 0; j < 32; ++j) {
    rows[j] = j < k ? pc.rows_out.v[base + uint(j)] : 0u;
    emit[j] = j < k ? pc.emit_rows.v[j] : 0u;
    full = full && (rows[j] & emit[j]) == emit[j];
  }
  for (uint e = e0; e < e1 && !full; ++e) {
    const uint t = pc.vals.v[e];
    if (raster_triangle(t, p, w, eu, ev, k, rows)) {
      // Every emitting sample blocked: no later triangle can change the mask.
      full = true;
      for (int j = 0; j < 32; ++j) full = full && (rows[j] & emit[j]) == emit[j];
    }
  }
  for (int j = 0; j < 32; ++j)
    if (j < k) pc.rows_out.v[base + uint(j)] = rows[j] & emit[j];
}
