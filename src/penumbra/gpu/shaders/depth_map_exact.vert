#version 460
// Exact depth pass (depth_exact.glsl): six vertices per caster (gl_VertexIndex / 6) draw the pixel
// box of its screen polygon — every texel centre the CPU could cover, with half a texel of margin,
// so no snapping can lose one; the fragment shader decides coverage. Culled or clipped-away
// triangles collapse to a point.
#include "depth_exact.glsl"

layout(push_constant) uniform Push {
  ScreenPolys polys;
  float resolution;
  float depth_scale;  // depth_map_exact.frag
} pc;

layout(location = 0) flat out uint triangle;

void main() {
  const uint t = uint(gl_VertexIndex) / 6u;
  const uint corner = uint(gl_VertexIndex) % 6u;  // two triangles: 0 1 2, 2 1 3
  triangle = t;
  ScreenPolys polys = pc.polys;
  if (polys.p[t].count == 0) {
    gl_Position = vec4(-2.0, -2.0, 0.0, 1.0);
    return;
  }
  const uint kCorners[6] = {0u, 1u, 2u, 2u, 1u, 3u};  // bit 0: right, bit 1: bottom
  const uint c = kCorners[corner];
  const float x = float((c & 1u) != 0u ? polys.p[t].x1 + 1 : polys.p[t].x0);
  const float y = float((c & 2u) != 0u ? polys.p[t].y1 + 1 : polys.p[t].y0);
  // Framebuffer row 0 is the CPU map's row 0 (screen y down): y_ndc = −1 there.
  gl_Position = vec4(2.0 * x / pc.resolution - 1.0, 2.0 * y / pc.resolution - 1.0, 0.0, 1.0);
}
