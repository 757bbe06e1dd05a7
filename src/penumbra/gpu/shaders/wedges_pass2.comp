#version 460
// `wedges` pass 2 [Assarsson 2003 III §3.2, IV §4.2; Forest 2008 Algorithm 3]: per active pixel,
// the wedges [first, first + chunk) of its tile's bin that hold it, each edge projected from the
// pixel and clipped to the light, its signed coverage — area(square ∩ sector) − area(triangle)
// (coverage.cpp box_sector), or the disk's sector minus triangle — added to the pixel's sum
// (initially its layered hard count), in bin order, in double: the CPU's sum. The last chunk
// writes V = 1 − clamp(sum, 0, 1). The coverage functions: wedge_coverage.glsl.
#include "common.glsl"
#include "dcs.glsl"
#include "wedge_coverage.glsl"

layout(buffer_reference, scalar) buffer Doubles { double v[]; };

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
      if (!wedge_contains(pc.wedges, w, p)) continue;
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
