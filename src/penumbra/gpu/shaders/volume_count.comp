#version 460
// The shadow-volume count without the graphics pipeline (devices with few graphics units): one
// workgroup per face of the volume, its threads taking the rows of the face's candidate rectangle
// (volume_setup.comp) and, per row, the pixels whose centres the rectangle spans (plus a pixel of
// margin: the exact test decides); each pixel gets volume.frag's test (volume_test in volume.glsl)
// and the face's weight by an integer atomicAdd — the stencil count, exactly.
#include "common.glsl"
#include "volume.glsl"

layout(buffer_reference, scalar) buffer Ints { int v[]; };

layout(push_constant) uniform Push {
  VolumeFaces faces;
  Doubles4 q;    // per pixel: shadow origin − camera, w = 1 for the active receivers, else 0
  Ints counts;   // per pixel, zeroed before
  uint n, width, height;
} pc;

/// The x interval (pixel centres) where the slab 0 ≤ (p − origin)·a ≤ |a|² holds on row centre y.
void clip_slab(vec2 origin, vec2 a, float y, inout float lo, inout float hi) {
  const float aa = dot(a, a);
  const float base = (y - origin.y) * a.y;
  if (a.x == 0.0) {
    if (base < -1.0 * sqrt(aa) || base > aa + sqrt(aa)) hi = lo - 1.0;  // a pixel of margin
    return;
  }
  float x0 = origin.x - base / a.x, x1 = origin.x + (aa - base) / a.x;
  if (x0 > x1) {
    const float t = x0;
    x0 = x1;
    x1 = t;
  }
  lo = max(lo, x0);
  hi = min(hi, x1);
}

void main() {
  const uint f = global_id() / 256u;
  if (f >= pc.n || pc.faces.f[f].n == 0) return;
  const vec2 r0 = pc.faces.f[f].rect[0], r1 = pc.faces.f[f].rect[1], r2 = pc.faces.f[f].rect[2];
  const vec2 r3 = pc.faces.f[f].rect[3];
  const float ymin = min(min(r0.y, r1.y), min(r2.y, r3.y));
  const float ymax = max(max(r0.y, r1.y), max(r2.y, r3.y));
  const int y0 = max(0, int(floor(ymin)) - 1), y1 = min(int(pc.height) - 1, int(ceil(ymax)));
  const int weight = pc.faces.f[f].weight;
  for (int y = y0 + int(gl_LocalInvocationIndex); y <= y1; y += 256) {
    float lo = -1e30, hi = 1e30;
    clip_slab(r0, r1 - r0, float(y) + 0.5, lo, hi);
    clip_slab(r0, r2 - r0, float(y) + 0.5, lo, hi);
    if (!(lo <= hi)) continue;
    const int x0 = max(0, int(floor(lo)) - 1), x1 = min(int(pc.width) - 1, int(ceil(hi)));
    for (int x = x0; x <= x1; ++x) {
      const uint pixel = uint(y) * pc.width + uint(x);
      const dvec4 q4 = pc.q.v[pixel];
      if (q4.w != 0.0 && volume_test(pc.faces, f, q4.xyz))
        atomicAdd(pc.counts.v[pixel], weight);
    }
  }
}
