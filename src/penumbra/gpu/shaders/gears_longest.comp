#version 460
// The most pairs any cell holds: how many chunks the rasterization dispatches (gears_raster.comp).
#include "common.glsl"

layout(push_constant) uniform Push {
  Uints begin;
  Uints end;
  Uints longest;  // [0], zero-filled before
  uint n;         // cells
} pc;

void main() {
  const uint c = global_id();
  if (c < pc.n) atomicMax(pc.longest.v[0], pc.end.v[c] - pc.begin.v[c]);
}
