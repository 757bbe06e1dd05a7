#version 460
// dcs step 3 [Forest 2008 eq. 4.1, §4.3.3]: per active pixel, the CPU's three outcomes —
// the umbra early-out (the centre count exceeds every possible decrement: uniform 0), no covered
// edge (every sample has the centre's counts: uniform t), or the per-sample visibility Sat(D) of
// the opaque class attenuated by the semi-opaque ones — then the masks and V = mean over the
// emitting samples, summed in the CPU's (band) order. A textured light's weighting is the host's
// (per-sample visibility written out; state[2a] = 2 marks such pixels).
#include "common.glsl"
#include "dcs.glsl"

layout(push_constant) uniform Push {
  Ints centre;     // class·na + pixel
  Ints state;      // per pixel: any covered edge, Σ |step| of class 0
  Ints counters;   // (class·n + sample)·na + pixel
  Floats attenuation;  // class·table + count: t^count (exact) or (1 − t)·count (paper), float
  Uints emit_index;    // per sorted sample: emits (bit 16) | LightSamples index
  Floats lit;
  Uints masks;         // words per pixel
  Floats sample_vis;   // na·n, textured lights only
  uint na, n, classes, table, paper, words, want_vis;
  uint sample_stride;  // 0, or n: each pixel's own samples
} pc;

/// Dcs pass_through: the light left after `count` crossings of class j's surfaces.
float pass_through(float vis, uint j, int count) {
  if (count <= 0 || vis == 0.0) return vis;
  const float f = pc.attenuation.v[j * pc.table + min(uint(count), pc.table - 1u)];
  precise const float r = pc.paper != 0u ? max(0.0, vis - f) : vis * f;
  return r;
}

void block_all(uint a) {
  for (uint s = 0u; s < pc.n; ++s) {
    const uint e = pc.emit_index.v[a * pc.sample_stride + s];
    if ((e & 0x10000u) != 0u) {
      const uint idx = e & 0xffffu;
      pc.masks.v[a * pc.words + (idx >> 5)] |= 1u << (idx & 31u);
    }
  }
}

void main() {
  const uint a = global_id();
  if (a >= pc.na) return;
  const int d0 = pc.centre.v[a];
  const bool any_covered = pc.state.v[2u * a] != 0;
  const int abs0 = pc.state.v[2u * a + 1u];
  if (d0 > abs0 || !any_covered) {
    float t = d0 > 0 ? 0.0 : 1.0;
    if (d0 <= abs0)
      for (uint j = 1u; j < pc.classes && t > 0.0; ++j)
        t = pass_through(t, j, pc.centre.v[j * pc.na + a]);
    if (t == 0.0) block_all(a);
    pc.lit.v[a] = t;
    return;
  }
  precise float seen = 0.0;
  int total = 0;
  for (uint s = 0u; s < pc.n; ++s) {
    float vis = pc.counters.v[s * pc.na + a] > 0 ? 0.0 : 1.0;
    for (uint j = 1u; j < pc.classes; ++j)
      vis = pass_through(vis, j, pc.counters.v[(j * pc.n + s) * pc.na + a]);
    const uint e = pc.emit_index.v[a * pc.sample_stride + s];
    const bool emits = (e & 0x10000u) != 0u;
    if (emits && vis == 0.0) {
      const uint idx = e & 0xffffu;
      pc.masks.v[a * pc.words + (idx >> 5)] |= 1u << (idx & 31u);
    }
    if (pc.want_vis != 0u) pc.sample_vis.v[a * pc.n + s] = vis;
    seen += emits ? vis : 0.0;
    total += emits ? 1 : 0;
  }
  // The quotient in double, rounded once to float: the correctly rounded float division of the CPU
  // (Vulkan allows float division 2.5 ulp).
  pc.lit.v[a] = total > 0 ? min(1.0, float(double(seen) / double(total))) : 1.0;
  if (pc.want_vis != 0u) pc.state.v[2u * a] = 2;
}
