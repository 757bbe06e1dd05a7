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
// Each pixel walks the prefix of its cell's list that its depth cut keeps, deepest first, and
// skips the triangles the CPU's per-pixel tests drop (slabs, shadow box) before their lines.
//
// Loops: a dispatch walks at most `chunk` triangles of a cell (the host dispatches the chunks of
// the longest cell in turn, OR-ing into rows_out): llvmpipe (lavapipe) stops any loop after 65535
// iterations in total, counting a nested loop's iterations across its enclosing loop's, so
// chunk × 32 rows × 4 lines stays below that; with alpha-tested or semi-opaque triangles, whose
// covered samples are visited one by one, the host takes chunks of 50 000 / (k² + k + 1).
#extension GL_EXT_control_flow_attributes : require
#include "common.glsl"

layout(push_constant) uniform Push {
  Vec4s pix;   // per active pixel: p, w, eu, ev, slab bounds (w.w, eu.w: solids outside)
  Vec4s tris;  // 3 per triangle
  Uints cell;  // per active pixel (~0: other side)
  Uints begin;
  Uints end;
  Uints vals;       // sorted triangle ids
  Uints rows_out;   // k words per active pixel, then (semi-opaque scenes) k² floats per pixel
  Uints emit_rows;  // k words: the samples the light emits from
  uint n;
  int k;
  uint first;  // this dispatch: walk_range's entries first … first + chunk − 1
  uint chunk;
  vec2 uv_lo;  // bounding box of the sample positions
  vec2 uv_hi;
  Vec4s alpha;      // 6 per triangle: (texel offset, width, height, 1 = alpha-tested),
                    // uv0 uv1, (uv2, transmittance), slab bounds, plane (2)
  Uints texels;     // alpha textures: 1 where the texel blocks (alpha ≥ the cutoff)
  Floats samples;   // light uv of sample s at 2s, 2s + 1
  uint flags;       // 2: deepest first, 4: the pixel's culls, 8: the hidden-shadow test
} pc;

#include "gears_lines.glsl"

/// ORs triangle t's coverage of the k×k samples into rows; false when it sets no bit. A
/// semi-opaque triangle instead scales the transmittance of each sample it covers (the pixel's
/// k² floats from word `trans_base` of rows_out).
bool raster_triangle(uint t, vec3 p, vec3 w, vec3 eu, vec3 ev, int k, uint trans_base,
                     inout uint rows[32]) {
  const float kf = float(k);
  ivec4 box;
  bool boxed;
  if (!shadow_box(t, p, eu, ev, k, pc.uv_lo, pc.uv_hi, box, boxed)) return false;
  const int j0 = box.z, j1 = box.w;
  if (boxed && (pc.flags & 8u) != 0u) {
    // The CPU's hidden-shadow test: a shadow whose box holds only samples already blocked
    // changes nothing (a semi-opaque layer over them neither: their V is 0).
    const uint need = (2u << uint(box.y)) - (1u << uint(box.x));  // i1 = 31: 2 << 31 wraps to 0
    bool hidden = true;
    for (int j = j0; j <= j1; ++j) hidden = hidden && (rows[j] & need) == need;
    if (hidden) return false;
  }
  float la[4], lb[4], lc[4];
  if (!triangle_lines(t, p, w, eu, ev, pc.uv_lo, pc.uv_hi, la, lb, lc)) return false;
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
  const bool alpha_tested = pc.alpha.v[6u * t].w != 0.0;
  const float transmittance = transmittance_of(t);
  for (int j = j0; j <= j1; ++j) {
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
          if (!alpha_blocks_at(t, la, lb, lc, pc.samples.v[2 * (j * k + i)],
                               pc.samples.v[2 * (j * k + i) + 1])) span &= ~(1u << uint(i));
      if (transmittance > 0.0) {
        for (uint bits = span; bits != 0u; bits &= bits - 1u)
          attenuate(pc.rows_out, trans_base + uint(j * k + findLSB(bits)), transmittance);
        continue;
      }
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
  // The whole vec4 at once: p and the depth cut (w). (Read as .w on its own after .xyz,
  // lavapipe returned x.)
  const vec4 p_cut = pc.pix.v[5u * a];
  const vec3 p = p_cut.xyz;
  const vec4 w_out = pc.pix.v[5u * a + 1u], eu_out = pc.pix.v[5u * a + 2u];
  const vec3 w = w_out.xyz, eu = eu_out.xyz;
  // The solids the pixel is certified outside of (the plane test's solid cull).
  const uvec2 outside = uvec2(floatBitsToUint(w_out.w), floatBitsToUint(eu_out.w));
  const vec3 ev = pc.pix.v[5u * a + 3u].xyz;
  uint e0, e1;
  if (!walk_range(pc.begin.v[c], pc.end.v[c], p_cut.w, pc.first, pc.chunk, pc.flags,
                  e0, e1))
    return;
  const bool descending = (pc.flags & 2u) != 0u;
  const bool slab_cull = (pc.flags & 4u) != 0u;
  const vec4 slab = pc.pix.v[5u * a + 4u];
  const uint base = a * uint(k);
  // Semi-opaque occluders: the pixels' per-sample transmittances follow the rows in rows_out.
  const uint trans_base = pc.n * uint(k) + a * uint(k * k);
  uint rows[32];
  uint emit[32];
  bool full = true;
  for (int j = 0; j < 32; ++j) {
    rows[j] = j < k ? pc.rows_out.v[base + uint(j)] : 0u;
    emit[j] = j < k ? pc.emit_rows.v[j] : 0u;
    full = full && (rows[j] & emit[j]) == emit[j];
  }
  for (uint i = 0u; i < e1 - e0 && !full; ++i) {
    const uint t = pc.vals.v[descending ? e1 - 1u - i : e0 + i];
    if (slab_cull && !(in_slabs(t, slab) && plane_keeps(t, p, outside))) continue;
    if (raster_triangle(t, p, w, eu, ev, k, trans_base, rows)) {
      // Every emitting sample blocked: no later triangle can change the mask.
      full = true;
      for (int j = 0; j < 32; ++j) full = full && (rows[j] & emit[j]) == emit[j];
    }
  }
  for (int j = 0; j < 32; ++j)
    if (j < k) pc.rows_out.v[base + uint(j)] = rows[j] & emit[j];
}
