#version 460
// Shadow-volume faces (volume.glsl): six vertices per face (gl_VertexIndex / 6) draw its candidate
// rectangle; culled faces collapse to a point.
#include "volume.glsl"

layout(push_constant) uniform Push {
  VolumeFaces faces;
  Doubles4 q;  // volume.frag
  vec2 size;   // framebuffer width, height
} pc;

layout(location = 0) flat out uint face;

void main() {
  const uint f = uint(gl_VertexIndex) / 6u;
  const uint kCorners[6] = {0u, 1u, 2u, 2u, 1u, 3u};
  face = f;
  VolumeFaces faces = pc.faces;
  if (faces.f[f].n == 0) {
    gl_Position = vec4(-2.0, -2.0, 0.0, 1.0);
    return;
  }
  const vec2 p = faces.f[f].rect[kCorners[uint(gl_VertexIndex) % 6u]];
  // Framebuffer row 0 is screen row 0 (y down): y_ndc = −1 there.
  gl_Position = vec4(2.0 * p / pc.size - 1.0, 0.0, 1.0);
}
