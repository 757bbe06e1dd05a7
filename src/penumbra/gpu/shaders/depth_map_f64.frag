#version 460
// Stores the view depth of the nearest caster, recomputed in double precision at the texel centre
// (devices with shaderFloat64): the ray through the texel centre, with unit forward component,
// meets the triangle's plane at t = view depth. The CPU rasterizer's 1/w interpolation in double
// is the same quantity, so both maps round to the same float almost everywhere.
#extension GL_EXT_buffer_reference : require
#extension GL_EXT_scalar_block_layout : require
#extension GL_EXT_shader_explicit_arithmetic_types_float64 : require

layout(buffer_reference, scalar) buffer Vec4s { vec4 v[]; };
layout(buffer_reference, scalar) buffer View {
  dvec3 eye;
  dvec3 right;
  dvec3 up;
  dvec3 forward;
  double tan_half_x;
  double tan_half_y;
  double resolution;
};

layout(push_constant) uniform Push {
  Vec4s vertices;
  View view;
} pc;

layout(location = 0) in float view_depth;
layout(location = 1) flat in uint triangle;
layout(location = 0) out float stored_depth;

void main() {
  View v = pc.view;
  const dvec2 texel = dvec2(floor(gl_FragCoord.xy)) + 0.5;
  const dvec3 dir = v.forward + (2.0 * texel.x / v.resolution - 1.0) * v.tan_half_x * v.right +
                    (1.0 - 2.0 * texel.y / v.resolution) * v.tan_half_y * v.up;
  const uint t = triangle * 3u;
  const dvec3 a = dvec3(pc.vertices.v[t].xyz), b = dvec3(pc.vertices.v[t + 1u].xyz),
              c = dvec3(pc.vertices.v[t + 2u].xyz);
  const dvec3 n = cross(b - a, c - a);
  const double den = dot(n, dir);
  const double depth = dot(n, a - v.eye) / den;
  // A grazing triangle (den ≈ 0) keeps the interpolated depth.
  stored_depth = abs(den) > 0.0 && depth > 0.0 ? float(depth) : view_depth;
}
