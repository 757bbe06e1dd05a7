#version 460
// GEARS step 4, per sample [Wang 2014 §4.2]: per pixel, every triangle of its cell tested against
// each light sample by its four lines (shadows/gears/raster.cpp raster_samples, operation for
// operation, `precise`): any sample positions — irregular and per-pixel patterns, k up to 64, a
// point light (one sample at the light). The pixel's mask is `words` 32-bit words, sample s at bit
// s % 32 of word s / 32; only emitting samples are kept.
//
// Loops: a dispatch walks at most `chunk` triangles of a cell (llvmpipe stops an invocation after
// 65535 loop iterations in all; a triangle costs one per sample, plus the alpha tests).
#extension GL_EXT_control_flow_attributes : require
#include "common.glsl"

const int kMaxWords = 128;  // 64 × 64 samples

layout(push_constant) uniform Push {
  Vec4s pix;   // per active pixel: p, w, eu, ev, slab bounds (w.w, eu.w: solids outside)
  Vec4s tris;  // 3 per triangle
  Uints cell;  // per active pixel (~0: other side)
  Uints begin;
  Uints end;
  Uints vals;       // sorted triangle ids
  Uints words_out;  // `words` per active pixel, then (semi-opaque scenes) ns floats per pixel
  Uints emit;       // `words` (shared) or `words` per active pixel (per_pixel)
  Floats samples;   // light uv of sample s at 2s, 2s + 1 (shared) or per active pixel (per_pixel)
  Vec4s alpha;      // 6 per triangle: (texel offset, width, height, 1 = alpha-tested),
                    // uv0 uv1, (uv2, transmittance), slab bounds, plane (2)
  Uints texels;     // alpha textures: 1 where the texel blocks (alpha ≥ the cutoff)
  uint n;
  uint ns;     // samples tested (1 for a point light)
  uint words;  // ⌈ns / 32⌉
  uint first;  // this dispatch: walk_range's entries first … first + chunk − 1
  uint chunk;
  uint flags;   // 1: samples and emitting bits per pixel, 2: deepest first, 4: the depth cut
  vec2 uv_lo;   // bounding box of the sample positions
  vec2 uv_hi;
} pc;

#include "gears_lines.glsl"

const uint kLutAll = 0xffffffffu, kLutNone = 0xfffffffeu;

/// Diamond angle of a direction in [0, 4): monotonic in the true angle (gears/lut.cpp).
float diamond_angle(float x, float y) {
  precise float r;
  if (y >= 0.0) r = x >= 0.0 ? y / (x + y) : 1.0 - x / (-x + y);
  else r = x < 0.0 ? 2.0 - y / (-x - y) : 3.0 + x / (x - y);
  return r;
}

/// gears::EdgeLut::lookup: the offset in texels of the mask of the samples with
/// a + b·u + c·v ≥ 0 (the line quantized to an (angle, offset) bin), or kLutAll / kLutNone.
/// texels[1 … 3]: angles, offsets, the samples' radius around (½, ½).
uint lut_lookup(uint table, float a, float b, float c) {
  const int angles = int(pc.texels.v[1]), offsets = int(pc.texels.v[2]);
  const float radius = uintBitsToFloat(pc.texels.v[3]);
  precise float len = sqrt(b * b + c * c);
  precise float centre = a + 0.5 * (b + c);
  if (!(len > 0.0)) return centre >= 0.0 ? kLutAll : kLutNone;
  precise float rho = centre / len;
  if (rho >= radius) return kLutAll;
  if (rho < -radius) return kLutNone;
  precise float fa = diamond_angle(b, c) * (float(angles) * 0.25);
  precise float fo = (rho / radius + 1.0) * 0.5 * float(offsets);
  const int ai = min(angles - 1, int(fa));
  const int oi = clamp(int(fo), 0, offsets - 1);
  // A row of the table: ⌈ns / 64⌉ 64-bit words, as 32-bit halves.
  const uint row = 2u * ((pc.ns + 63u) / 64u);
  return table + uint(ai * offsets + oi) * row;
}

void main() {
  const uint a = global_id();
  if (a >= pc.n) return;
  const uint c = pc.cell.v[a];
  if (c == 0xffffffffu) return;
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
  const uint base = a * pc.words;
  // Semi-opaque occluders: the pixels' per-sample transmittances follow the masks in words_out.
  const uint trans_base = pc.n * pc.words + a * pc.ns;
  const bool per_pixel = (pc.flags & 1u) != 0u;
  const uint emit_base = per_pixel ? base : 0u;
  const uint sample_base = per_pixel ? 2u * a * pc.ns : 0u;
  const uint lut_table = pc.texels.v[0];  // the LUT variant: its table's offset in texels
  uint bits[kMaxWords];
  bool full = true;
  for (uint i = 0u; i < pc.words; ++i) {
    bits[i] = pc.words_out.v[base + i];
    const uint em = pc.emit.v[emit_base + i];
    full = full && (bits[i] & em) == em;
  }
  for (uint i = 0u; i < e1 - e0 && !full; ++i) {
    const uint t = pc.vals.v[descending ? e1 - 1u - i : e0 + i];
    if (slab_cull && !(in_slabs(t, slab) && plane_keeps(t, p, outside))) continue;
    ivec4 box;
    bool boxed;
    if (!shadow_box(t, p, eu, ev, 0, pc.uv_lo, pc.uv_hi, box, boxed)) continue;
    float la[4], lb[4], lc[4];
    if (!triangle_lines(t, p, w, eu, ev, pc.uv_lo, pc.uv_hi, la, lb, lc)) continue;
    const bool alpha_tested = pc.alpha.v[6u * t].w != 0.0;
    const float transmittance = transmittance_of(t);
    bool any = false;
    if (lut_table != 0u) {
      // [Wang 2014 §4.3]: the samples the triangle covers are the AND of its lines' table masks.
      uint m[4];
      bool none = false;
      [[unroll]] for (int l = 0; l < 4; ++l) {
        m[l] = lut_lookup(lut_table, la[l], lb[l], lc[l]);
        none = none || m[l] == kLutNone;
      }
      for (uint wi = 0u; wi < pc.words && !none; ++wi) {
        uint cover = wi + 1u < pc.words || (pc.ns & 31u) == 0u ? ~0u : (1u << (pc.ns & 31u)) - 1u;
        [[unroll]] for (int l = 0; l < 4; ++l)
          if (m[l] != kLutAll) cover &= pc.texels.v[m[l] + wi];
        if (!alpha_tested && !(transmittance > 0.0)) {
          bits[wi] |= cover;
          any = any || cover != 0u;
          continue;
        }
        for (; cover != 0u; cover &= cover - 1u) {
          const uint s = 32u * wi + uint(findLSB(cover));
          const float su = pc.samples.v[2u * s], sv = pc.samples.v[2u * s + 1u];
          if (alpha_tested && !alpha_blocks_at(t, la, lb, lc, su, sv)) continue;
          if (transmittance > 0.0) {
            attenuate(pc.words_out, trans_base + s, transmittance);
            continue;
          }
          bits[wi] |= 1u << (s & 31u);
          any = true;
        }
      }
    }
    for (uint s = 0u; s < pc.ns && lut_table == 0u; ++s) {
      const float su = pc.samples.v[sample_base + 2u * s];
      const float sv = pc.samples.v[sample_base + 2u * s + 1u];
      precise const float h0 = la[0] + lb[0] * su + lc[0] * sv;
      precise const float h1 = la[1] + lb[1] * su + lc[1] * sv;
      precise const float h2 = la[2] + lb[2] * su + lc[2] * sv;
      precise const float h3 = la[3] + lb[3] * su + lc[3] * sv;
      if (!(h0 >= 0.0 && h1 >= 0.0 && h2 >= 0.0 && h3 >= 0.0)) continue;
      if (alpha_tested && !alpha_blocks_at(t, la, lb, lc, su, sv)) continue;
      if (transmittance > 0.0) {
        attenuate(pc.words_out, trans_base + s, transmittance);
        continue;
      }
      bits[s >> 5] |= 1u << (s & 31u);
      any = true;
    }
    if (any) {
      // Every emitting sample blocked: no later triangle can change the mask.
      full = true;
      for (uint i = 0u; i < pc.words; ++i) {
        const uint em = pc.emit.v[emit_base + i];
        full = full && (bits[i] & em) == em;
      }
    }
  }
  for (uint i = 0u; i < pc.words; ++i) pc.words_out.v[base + i] = bits[i] & pc.emit.v[emit_base + i];
}
