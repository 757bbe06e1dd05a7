// Shared by every compute shader: 1D workgroups of 256 threads (commands.hpp: kGroupSize), buffers
// as device addresses in push constants.
#extension GL_EXT_buffer_reference : require
#extension GL_EXT_scalar_block_layout : require

layout(local_size_x = 256) in;

layout(buffer_reference, scalar) buffer Uints { uint v[]; };
layout(buffer_reference, scalar) buffer Floats { float v[]; };
layout(buffer_reference, scalar) buffer Vec4s { vec4 v[]; };

/// The flat workgroup index (dispatches of more than 32768 groups spill into y).
uint group_id() { return gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x; }
/// The flat thread index.
uint global_id() { return group_id() * 256u + gl_LocalInvocationIndex; }
