#version 460
// Depth-map lookups in double, the CPU's precision (devices with shaderFloat64).
#define LOOKUP_F64 1
#include "shadow_lookup.glsl"
