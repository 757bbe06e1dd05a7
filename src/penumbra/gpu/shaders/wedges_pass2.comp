#version 460
// `wedges` pass 2 for an untextured light (wedges_pass2.glsl).
#include "wedges_pass2.glsl"
