#version 460
// `wedge_blend` per pixel for an untextured light (wedge_blend_pass2.glsl).
#include "wedge_blend_pass2.glsl"
