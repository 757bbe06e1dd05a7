#version 460
// The CPU's per-pixel test of one shadow-volume face (shadow_volume.cpp) at this pixel's shadow
// origin: inside the face's cone (its edge planes through the camera, with the tie bits), and the
// face behind the receiver (its plane; far caps always are). Writes the signed weight, summed by
// additive blending.
#include "volume.glsl"

layout(push_constant) uniform Push {
  VolumeFaces faces;
  Doubles4 q;  // per pixel: shadow origin − camera, w = 1 for the active receivers, else 0
  vec2 size;
} pc;

layout(location = 0) flat in uint face;
layout(location = 0) out float count;

void main() {
  const uint pixel = uint(gl_FragCoord.y) * uint(pc.size.x) + uint(gl_FragCoord.x);
  const dvec4 q4 = pc.q.v[pixel];
  if (q4.w == 0.0 || !volume_test(pc.faces, face, q4.xyz)) discard;
  count = float(pc.faces.f[face].weight);
}
