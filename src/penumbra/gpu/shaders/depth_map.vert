#version 460
// Depth-map pass [Forest 2008 §2.2.2] of devices without shaderFloat64 (the others draw the
// exact pass, depth_exact.glsl): caster triangles (world positions pulled by gl_VertexIndex)
// through the light's square pinhole projection (raster/projection.hpp). Clip w is the view depth;
// clip z = near gives the depth near/w ("reversed z": float keeps its relative precision at every
// distance), tested GREATER; w ≥ near is the CPU's near-plane clip. Coverage is the hardware's
// (vertices snapped to its sub-texel grid), so edge texels may differ from the CPU map.
#extension GL_EXT_buffer_reference : require
#extension GL_EXT_scalar_block_layout : require

layout(buffer_reference, scalar) buffer Vec4s { vec4 v[]; };

layout(push_constant) uniform Push {
  Vec4s vertices;  // (8 bytes of padding follow: std430 aligns vec4 to 16)
  vec4 eye;      // xyz; w = near
  vec4 right;    // xyz; w = tan_half_x
  vec4 up;       // xyz; w = tan_half_y
  vec4 forward;  // xyz
} pc;

layout(location = 0) out float view_depth;

void main() {
  const vec3 rel = pc.vertices.v[gl_VertexIndex].xyz - pc.eye.xyz;
  const float x = dot(rel, pc.right.xyz) / pc.right.w;
  const float y = dot(rel, pc.up.xyz) / pc.up.w;
  const float w = dot(rel, pc.forward.xyz);
  view_depth = w;
  // Screen y grows downward on the CPU (row 0 at the top, y_ndc = +1): Vulkan's framebuffer row 0
  // is at y_ndc = −1, hence −y.
  gl_Position = vec4(x, -y, pc.eye.w, w);
}
