#version 460
// `wedge_blend` per pixel for a textured rectangular light: every share in emitted power per
// channel (wedge_blend_pass2.glsl, wedge_emission.glsl).
#define TEXTURED
#include "wedge_blend_pass2.glsl"
