#version 460
// Depth-map lookups in float (devices without shaderFloat64).
#include "shadow_lookup.glsl"
