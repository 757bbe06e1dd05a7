#version 460
// `wedges` pass 2 for a textured rectangular light: the per-channel coverage of wedge_emission.glsl
// (wedges_pass2.glsl).
#define TEXTURED
#include "wedges_pass2.glsl"
