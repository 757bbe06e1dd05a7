// Depth-map lookups over the G-buffer: `shadow_map` (k×k PCF [Reeves 1987]) and `pcss` (blocker
// search, penumbra width, variable PCF [Fernando 2005]), the CPU's ShadowMapLookup
// (shadows/depth_maps/shadow_map.cpp) line for line: the receiver-plane depth at each tap's texel
// centre minus constant + slope-scaled bias.
// Included by shadow_lookup.comp (float) and shadow_lookup_f64.comp (double, where the device has
// shaderFloat64: the CPU's precision, so both pick the same taps).
#include "common.glsl"

#ifdef LOOKUP_F64
#extension GL_EXT_shader_explicit_arithmetic_types_float64 : require
#define real double
#define rvec3 dvec3
#else
#define real float
#define rvec3 vec3
#endif

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
#ifdef LOOKUP_F64
  // The same in double (declared and read by the double variant only).
  dvec3 eye_d;
  dvec3 right_d;
  dvec3 up_d;
  dvec3 forward_d;
  double tan_half_x_d;
  double tan_half_y_d;
  double texel_tan_d;
  double bias_d;
  double slope_bias_d;
  double light_width_d;
  double max_radius_d;
#endif
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
rvec3 eye_, right_, up_, forward_;
real tan_x_, tan_y_, texel_tan_, bias_constant_, bias_slope_, light_width_, max_radius_;
real sx_, sy_, depth_, bias_, plane_num_;
real den0_, den_di_, den_dj_;  // n · (direction through texel centre (i, j)), affine in i, j

void load_params() {
#ifdef LOOKUP_F64
  eye_ = P.eye_d, right_ = P.right_d, up_ = P.up_d, forward_ = P.forward_d;
  tan_x_ = P.tan_half_x_d, tan_y_ = P.tan_half_y_d, texel_tan_ = P.texel_tan_d;
  bias_constant_ = P.bias_d, bias_slope_ = P.slope_bias_d;
  light_width_ = P.light_width_d, max_radius_ = P.max_radius_d;
#else
  eye_ = P.eye, right_ = P.right, up_ = P.up, forward_ = P.forward;
  tan_x_ = P.tan_half_x, tan_y_ = P.tan_half_y, texel_tan_ = P.texel_tan;
  bias_constant_ = P.bias, bias_slope_ = P.slope_bias;
  light_width_ = P.light_width, max_radius_ = P.max_radius;
#endif
}

float stored(int i, int j) {
  const int r = P.resolution;
  if (i < 0 || j < 0 || i >= r || j >= r) return uintBitsToFloat(0x7f800000u);
  return pc.map.v[j * r + i];
}

real plane_depth(int i, int j) {
  const real den = den0_ + real(i) * den_di_ + real(j) * den_dj_;
  const real t = plane_num_ / den;
  if (!(abs(den) > 1e-12) || !(t > 0.0) || t > 4.0 * depth_ || t < 0.25 * depth_) return depth_;
  return t;
}

bool blocked(int i, int j) { return stored(i, j) < plane_depth(i, j) - bias_; }

bool setup(rvec3 p, rvec3 n) {
  const rvec3 rel = p - eye_;
  const real w = dot(rel, forward_);
  if (!(w > 0.0)) return false;
  const real r = real(P.resolution);
  sx_ = (0.5 + 0.5 * (dot(rel, right_) / tan_x_) / w) * r;
  sy_ = (0.5 - 0.5 * (dot(rel, up_) / tan_y_) / w) * r;
  depth_ = w;
  const rvec3 to_light = normalize(eye_ - p);
  const real cos_t = clamp(abs(dot(n, to_light)), real(1e-3), real(1.0));
  const real tan_t = min(sqrt(1.0 - cos_t * cos_t) / cos_t, real(100.0));
  bias_ = bias_constant_ + bias_slope_ * texel_tan_ * depth_ * tan_t;
  plane_num_ = dot(n, p - eye_);
  // As ShadowMapLookup::setup, term for term.
  const real n_right = tan_x_ * dot(n, right_);
  const real n_up = tan_y_ * dot(n, up_);
  den_di_ = 2.0 * n_right / r;
  den_dj_ = -2.0 * n_up / r;
  den0_ = dot(n, forward_) + (1.0 / r - 1.0) * n_right + (1.0 - 1.0 / r) * n_up;
  return true;
}

float shadow_map() {
  const int k = P.pcf;
  const real half_k = 0.5 * real(k - 1);
  int count = 0;
  for (int ty = 0; ty < k; ++ty)
    for (int tx = 0; tx < k; ++tx)
      count += blocked(int(floor(sx_ + real(tx) - half_k)), int(floor(sy_ + real(ty) - half_k))) ? 1 : 0;
  return 1.0 - float(count) / float(k * k);
}

float pcss() {
  const real z_r = depth_;
  const real z_min = max(real(uintBitsToFloat(pc.min_depth.v[0])), real(1e-9));
  const real w = light_width_;
  const real texel_tan = texel_tan_, max_radius = max_radius_;
  // 1. Blocker search over the light's footprint at the nearest caster depth.
  const real search = clamp(0.5 * w * max(z_r - z_min, real(0.0)) / (z_r * z_min) / texel_tan, real(0.5), max_radius);
  const int b = P.blocker_samples;
  real sum = 0.0;
  int found = 0;
  for (int by = 0; by < b; ++by)
    for (int bx = 0; bx < b; ++bx) {
      const real ox = ((real(bx) + 0.5) / real(b) * 2.0 - 1.0) * search;
      const real oy = ((real(by) + 0.5) / real(b) * 2.0 - 1.0) * search;
      const int i = int(floor(sx_ + ox)), j = int(floor(sy_ + oy));
      if (blocked(i, j)) {
        sum += stored(i, j);
        ++found;
      }
    }
  if (found == 0) return 1.0;
  const real z_b = sum / real(found);
  // 2. Penumbra width by similar triangles [Fernando 2005 eq. 1] → filter half-width in texels.
  const real radius = clamp(0.5 * w * max(z_r - z_b, real(0.0)) / (z_r * z_b) / texel_tan, real(0.5), max_radius);
  // 3. PCF.
  const int q = P.pcf_samples;
  int count = 0;
  for (int py = 0; py < q; ++py)
    for (int px = 0; px < q; ++px) {
      const real ox = ((real(px) + 0.5) / real(q) * 2.0 - 1.0) * radius;
      const real oy = ((real(py) + 0.5) / real(q) * 2.0 - 1.0) * radius;
      count += blocked(int(floor(sx_ + ox)), int(floor(sy_ + oy))) ? 1 : 0;
    }
  return 1.0 - float(count) / float(q * q);
}

void main() {
  const uint a = global_id();
  if (a >= pc.n) return;
  P = pc.prm;
  load_params();
  float v = 1.0;
  if (setup(rvec3(pc.points.v[2u * a].xyz), rvec3(pc.points.v[2u * a + 1u].xyz))) v = P.mode == 0 ? shadow_map() : pcss();
  pc.vis.v[a] = v;
}
