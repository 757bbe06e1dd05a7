#version 460
// Stores the view depth of the nearest caster (perspective-correct interpolation of w is exact:
// w is affine in world space).
layout(location = 0) in float view_depth;
layout(location = 0) out float stored_depth;

void main() { stored_depth = view_depth; }
