#version 460
// dcs step 1: every counter of every (class, sample, pixel) starts at the pixel's centre count of
// that class [Forest 2008 §4.1.1]. Counters are sample-major, (class·n + sample)·na + pixel, so
// neighbouring threads touch neighbouring words.
#include "common.glsl"
#include "dcs.glsl"

layout(push_constant) uniform Push {
  Ints centre;  // class·na + pixel
  Ints counters;
  uint na, n, total;
} pc;

void main() {
  const uint t = global_id();
  if (t >= pc.total) return;
  const uint a = t % pc.na, cls = t / pc.na / pc.n;
  pc.counters.v[t] = pc.centre.v[cls * pc.na + a];
}
