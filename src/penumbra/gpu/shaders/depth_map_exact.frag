#version 460
// Exact depth pass (depth_exact.glsl): rasterize_triangle's coverage test and 1/w interpolation at
// this texel centre, over the fan pieces of the caster's clipped screen polygon, in double
// (`precise`). The nearest depth wins through the depth attachment: gl_FragDepth is the view depth
// times a power of two (exact, so the float order is the depth order), tested LESS.
#include "depth_exact.glsl"

layout(push_constant) uniform Push {
  ScreenPolys polys;
  float resolution;
  float depth_scale;  // 2^-k ≥ 1 / the farthest caster point
} pc;

layout(location = 0) flat in uint triangle;
layout(location = 0) out float stored_depth;

void main() {
  const double px = double(floor(gl_FragCoord.x)) + 0.5, py = double(floor(gl_FragCoord.y)) + 0.5;
  float depth;
  if (!nearest_depth(pc.polys, triangle, px, py, depth)) discard;
  stored_depth = depth;
  gl_FragDepth = depth * pc.depth_scale;
}
