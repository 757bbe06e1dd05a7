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

precise double dot3(dvec3 a, dvec3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }

void main() {
  const uint pixel = uint(gl_FragCoord.y) * uint(pc.size.x) + uint(gl_FragCoord.x);
  const dvec4 q4 = pc.q.v[pixel];
  if (q4.w == 0.0) discard;
  const dvec3 q = q4.xyz;
  VolumeFaces faces = pc.faces;
  const int n = faces.f[face].n, own = faces.f[face].own;
  for (int e = 0; e < n; ++e) {
    precise const double d = dot3(faces.f[face].edge[e], q);
    if (d < 0.0 || (d == 0.0 && ((own >> e) & 1) == 0)) discard;
  }
  if (faces.f[face].has_plane != 0) {
    const double k = faces.f[face].plane_k;
    precise const double side = (dot3(faces.f[face].plane_n, q) + k) * k;
    if (!(side > 0.0)) discard;
  }
  count = float(faces.f[face].weight);
}
