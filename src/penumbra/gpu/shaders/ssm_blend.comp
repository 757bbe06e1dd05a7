#version 460
// `ssm` step 4 [Atty 2006 §3.4] per soft-shadow-map texel: the micro-patches of its 16×16 tile's
// bin [first, first + chunk), in patch order, whose penumbra extent holds the texel, each adding
// the fraction of the light it hides from the texel's receiver point (the back-projection onto the
// light and the product of the two clamped overlaps, shadows/depth_maps/ssm_maps.cpp
// patch_occlusion, in double) to the texel's float sum — the CPU's sums in the CPU's order.
// The paper blends each patch's extent into the map with the raster pipeline (additive blending,
// one quad per micro-patch); a gather per texel needs neither blending nor atomics.
#extension GL_EXT_shader_explicit_arithmetic_types_float64 : require
#include "common.glsl"

struct Patch {
  double px, py, hx, hy, zo;
  int i0, i1, j0, j1;
};
layout(buffer_reference, scalar) buffer Patches { Patch v[]; };

layout(push_constant) uniform Push {
  Patches patches;
  Uints bin_begin;    // per 16×16 tile, + 1
  Uints bin_entries;  // patch indices, in patch order
  Floats rmap;        // receiver depth per texel (+inf: none)
  Floats acc;         // the soft shadow map
  Uints touched;      // [0]: (patch, texel) pairs visited
  double tx0, ty1, dx, dy;  // the window (ssm.hpp Window)
  double lu, lv;            // the light's sides
  uint w, h, tiles_x, first, chunk;
} pc;

/// ssm::patch_occlusion.
double patch_occlusion(Patch p, double qx, double qy, double zr) {
  if (!(zr > p.zo) || !(p.zo > 0.0)) return 0.0;
  precise const double s = zr / max(zr - p.zo, zr * 1e-12);
  precise const double a = (qx + (p.px - p.hx - qx) * s) / pc.lu + 0.5;
  precise const double b = (qx + (p.px + p.hx - qx) * s) / pc.lu + 0.5;
  precise const double c = (qy + (p.py - p.hy - qy) * s) / pc.lv + 0.5;
  precise const double d = (qy + (p.py + p.hy - qy) * s) / pc.lv + 0.5;
  precise const double wx = clamp(b, 0.0, 1.0) - clamp(a, 0.0, 1.0);
  precise const double wy = clamp(d, 0.0, 1.0) - clamp(c, 0.0, 1.0);
  precise const double o = max(wx, 0.0) * max(wy, 0.0);
  return o;
}

void main() {
  const uint t = global_id();
  if (t >= pc.w * pc.h) return;
  const float zr = pc.rmap.v[t];
  if (!(zr < uintBitsToFloat(0x7f800000u))) return;
  const int i = int(t % pc.w), j = int(t / pc.w);
  const uint tile = uint(j / 16) * pc.tiles_x + uint(i / 16);
  const uint b1 = pc.bin_begin.v[tile + 1u];
  const uint from = pc.bin_begin.v[tile] + pc.first;
  if (from >= b1) return;
  const uint to = min(b1, from + pc.chunk);
  // Window::centre_x / centre_y, and the receiver point at the texel centre.
  precise const double cx = pc.tx0 + (double(i) + 0.5) * pc.dx;
  precise const double cy = pc.ty1 - (double(j) + 0.5) * pc.dy;
  precise const double qx = double(zr) * cx, qy = double(zr) * cy;
  float sum = pc.acc.v[t];
  uint visited = 0u;
  for (uint e = from; e < to; ++e) {
    const Patch p = pc.patches.v[pc.bin_entries.v[e]];
    if (i < p.i0 || i > p.i1 || j < p.j0 || j > p.j1) continue;
    ++visited;
    const double o = patch_occlusion(p, qx, qy, double(zr));
    if (o <= 0.0) continue;
    precise const float next = sum + float(o);
    sum = next;
  }
  pc.acc.v[t] = sum;
  if (visited > 0u) atomicAdd(pc.touched.v[0], visited);
}
