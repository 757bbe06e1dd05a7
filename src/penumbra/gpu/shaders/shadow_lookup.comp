#version 460
// Depth-map lookups over the G-buffer: `shadow_map` (k×k PCF [Reeves 1987]) and `pcss` (blocker
// search, penumbra width, variable PCF [Fernando 2005]), the CPU's ShadowMapLookup
// (shadows/depth_maps/shadow_map.cpp) line for line: the receiver-plane depth at each tap's texel
// centre minus constant + slope-scaled bias.
#include "common.glsl"

layout(buffer_reference, scalar) buffer LookupParams {
  vec3 eye;
  float tan_half_x;
  vec3 right;
  float tan_half_y;
  vec3 up;
  float texel_tan;
  vec3 forward;
  int resolution;
  float bias;
  float slope_bias;
  int mode;  // 0: shadow_map, 1: pcss
  int pcf;   // shadow_map: k×k taps
  float light_width;
  int blocker_samples;
  int pcf_samples;
  float max_radius;
};

layout(push_constant) uniform Push {
  LookupParams prm;
  Vec4s points;  // per active pixel: shadow origin, geometric normal (2 vec4)
  Floats map;
  Uints min_depth;  // float bits
  Floats vis;
  uint n;
} pc;

LookupParams P;
vec3 p_, n_;
float sx_, sy_, depth_, bias_, plane_num_;

float stored(int i, int j) {
  const int r = P.resolution;
  if (i < 0 || j < 0 || i >= r || j >= r) return uintBitsToFloat(0x7f800000u);
  return pc.map.v[j * r + i];
}

float plane_depth(int i, int j) {
  const float r = float(P.resolution);
  const vec3 dir = P.forward + (2.0 * (float(i) + 0.5) / r - 1.0) * P.tan_half_x * P.right +
                   (1.0 - 2.0 * (float(j) + 0.5) / r) * P.tan_half_y * P.up;
  const float den = dot(n_, dir);
  const float t = plane_num_ / den;
  if (!(abs(den) > 1e-12) || !(t > 0.0) || t > 4.0 * depth_ || t < 0.25 * depth_) return depth_;
  return t;
}

bool blocked(int i, int j) { return stored(i, j) < plane_depth(i, j) - bias_; }

bool setup(vec3 p, vec3 n) {
  p_ = p;
  n_ = n;
  const vec3 rel = p - P.eye;
  const float w = dot(rel, P.forward);
  if (!(w > 0.0)) return false;
  const float r = float(P.resolution);
  sx_ = (0.5 + 0.5 * (dot(rel, P.right) / P.tan_half_x) / w) * r;
  sy_ = (0.5 - 0.5 * (dot(rel, P.up) / P.tan_half_y) / w) * r;
  depth_ = w;
  const vec3 to_light = normalize(P.eye - p);
  const float cos_t = clamp(abs(dot(n, to_light)), 1e-3, 1.0);
  const float tan_t = min(sqrt(1.0 - cos_t * cos_t) / cos_t, 100.0);
  bias_ = P.bias + P.slope_bias * P.texel_tan * depth_ * tan_t;
  plane_num_ = dot(n, p - P.eye);
  return true;
}

float shadow_map() {
  const int k = P.pcf;
  const float half_k = 0.5 * float(k - 1);
  int count = 0;
  for (int ty = 0; ty < k; ++ty)
    for (int tx = 0; tx < k; ++tx)
      count += blocked(int(floor(sx_ + float(tx) - half_k)), int(floor(sy_ + float(ty) - half_k))) ? 1 : 0;
  return 1.0 - float(count) / float(k * k);
}

float pcss() {
  const float z_r = depth_;
  const float z_min = max(uintBitsToFloat(pc.min_depth.v[0]), 1e-9);
  const float w = P.light_width;
  // 1. Blocker search over the light's footprint at the nearest caster depth.
  const float search = clamp(0.5 * w * max(z_r - z_min, 0.0) / (z_r * z_min) / P.texel_tan, 0.5, P.max_radius);
  const int b = P.blocker_samples;
  float sum = 0.0;
  int found = 0;
  for (int by = 0; by < b; ++by)
    for (int bx = 0; bx < b; ++bx) {
      const float ox = ((float(bx) + 0.5) / float(b) * 2.0 - 1.0) * search;
      const float oy = ((float(by) + 0.5) / float(b) * 2.0 - 1.0) * search;
      const int i = int(floor(sx_ + ox)), j = int(floor(sy_ + oy));
      if (blocked(i, j)) {
        sum += stored(i, j);
        ++found;
      }
    }
  if (found == 0) return 1.0;
  const float z_b = sum / float(found);
  // 2. Penumbra width by similar triangles [Fernando 2005 eq. 1] → filter half-width in texels.
  const float radius = clamp(0.5 * w * max(z_r - z_b, 0.0) / (z_r * z_b) / P.texel_tan, 0.5, P.max_radius);
  // 3. PCF.
  const int q = P.pcf_samples;
  int count = 0;
  for (int py = 0; py < q; ++py)
    for (int px = 0; px < q; ++px) {
      const float ox = ((float(px) + 0.5) / float(q) * 2.0 - 1.0) * radius;
      const float oy = ((float(py) + 0.5) / float(q) * 2.0 - 1.0) * radius;
      count += blocked(int(floor(sx_ + ox)), int(floor(sy_ + oy))) ? 1 : 0;
    }
  return 1.0 - float(count) / float(q * q);
}

void main() {
  const uint a = global_id();
  if (a >= pc.n) return;
  P = pc.prm;
  float v = 1.0;
  if (setup(pc.points.v[2u * a].xyz, pc.points.v[2u * a + 1u].xyz)) v = P.mode == 0 ? shadow_map() : pcss();
  pc.vis.v[a] = v;
}
