#version 460
// `silhouette_map`'s final rendering [Valient 2005 §2.2]: per active pixel the depth-map test,
// the silhouette depth test and the bilinearly filtered edge distance combined by eq. 4 in the
// gradient table — hard mode one sample (and the plain shadow map where the four texels the
// filter reads agree), soft mode (§2.2.1) four samples in the 2D table. The CPU's compute() and
// ShadowMapLookup line for line, in double (`precise`: no FMAs the CPU does not do); the table
// is the CPU's (host-built floats).
#extension GL_EXT_shader_explicit_arithmetic_types_float64 : require
#include "common.glsl"

layout(buffer_reference, scalar) buffer Params {
  dvec3 eye, right, up, forward;
  double tan_half_x, tan_half_y, texel_tan, resolution;
  double bias, slope_bias;  // the depth map's
  double half_band, radius, row_width_max;
  double cos_k[4], sin_k[4];  // the soft samples' directions, kπ(¼ + ½k) (host's cos and sin)
  int rows;
};

layout(push_constant) uniform Push {
  Params prm;
  Vec4s points;     // per active pixel: shadow origin, geometric normal (2 vec4)
  Floats map;       // depth map, kEmptyDepth where empty
  Floats distance;  // the silhouette layer
  Floats depth;
  Floats table;     // rows × 4 × 257
  Floats vis;
  uint n;
} pc;

const int kQuarter = 256;

Params P;
int res_;
double sx_, sy_, depth_, bias_, plane_num_, den0_, den_di_, den_dj_;

double dot3(dvec3 a, dvec3 b) {
  precise const double d = a.x * b.x + a.y * b.y + a.z * b.z;  // glm's order
  return d;
}

float stored(int i, int j) {
  if (i < 0 || j < 0 || i >= res_ || j >= res_) return uintBitsToFloat(0x7f800000u);
  return pc.map.v[j * res_ + i];
}

double plane_depth(int i, int j) {
  precise const double den = den0_ + double(i) * den_di_ + double(j) * den_dj_;
  precise const double t = plane_num_ / den;
  if (!(abs(den) > 1e-12) || !(t > 0.0) || t > 4.0 * depth_ || t < 0.25 * depth_) return depth_;
  return t;
}

bool blocked(int i, int j) {
  precise const double limit = plane_depth(i, j) - bias_;
  return double(stored(i, j)) < limit;
}

/// ShadowMapLookup::setup (projection as Projection::to_clip / to_screen).
bool setup(dvec3 p, dvec3 n) {
  precise const dvec3 rel = p - P.eye;
  const double w = dot3(rel, P.forward);
  if (!(w > 0.0)) return false;
  precise const double cx = dot3(rel, P.right) / P.tan_half_x;
  precise const double cy = dot3(rel, P.up) / P.tan_half_y;
  precise const double inv_w = 1.0 / w;
  precise const double sx = (0.5 + 0.5 * cx * inv_w) * P.resolution;
  precise const double sy = (0.5 - 0.5 * cy * inv_w) * P.resolution;
  sx_ = sx, sy_ = sy, depth_ = w;
  precise const dvec3 v = P.eye - p;
  precise const double inv_len = 1.0 / sqrt(dot3(v, v));  // glm::normalize
  precise const dvec3 to_light = v * inv_len;
  const double cos_t = clamp(abs(dot3(n, to_light)), 1e-3, 1.0);
  precise const double tan_t = min(sqrt(1.0 - cos_t * cos_t) / cos_t, 100.0);
  precise const double bias = P.bias + P.slope_bias * P.texel_tan * w * tan_t;
  bias_ = bias;
  plane_num_ = dot3(n, p - P.eye);
  precise const double n_right = P.tan_half_x * dot3(n, P.right);
  precise const double n_up = P.tan_half_y * dot3(n, P.up);
  precise const double di = 2.0 * n_right / P.resolution;
  precise const double dj = -2.0 * n_up / P.resolution;
  precise const double d0 = dot3(n, P.forward) + (1.0 / P.resolution - 1.0) * n_right +
                            (1.0 - 1.0 / P.resolution) * n_up;
  den_di_ = di, den_dj_ = dj, den0_ = d0;
  return true;
}

double layer_distance(int x, int y) {
  if (x < 0 || y < 0 || x >= res_ || y >= res_) return -P.half_band;
  const int i = y * res_ + x;
  // Off every thick silhouette: ±half_band from the depth map's coverage (the CPU's fill, float).
  if (isinf(pc.depth.v[i])) return double(float(pc.map.v[i] < 3.40282347e38 ? P.half_band : -P.half_band));
  return double(pc.distance.v[i]);
}

/// Bilinearly filtered edge distance (the paper's hardware filtering).
double edge_distance(double sx, double sy) {
  precise const double fx = sx - 0.5, fy = sy - 0.5;
  const int x0 = int(floor(fx)), y0 = int(floor(fy));
  precise const double ax = fx - double(x0), ay = fy - double(y0);
  precise const double v = (1.0 - ay) * ((1.0 - ax) * layer_distance(x0, y0) + ax * layer_distance(x0 + 1, y0)) +
                           ay * ((1.0 - ax) * layer_distance(x0, y0 + 1) + ax * layer_distance(x0 + 1, y0 + 1));
  return v;
}

double edge_depth(double sx, double sy) {
  const int x = int(floor(sx)), y = int(floor(sy));
  if (x < 0 || y < 0 || x >= res_ || y >= res_) return double(uintBitsToFloat(0x7f800000u));
  return double(pc.depth.v[y * res_ + x]);
}

/// std::lround for the row index.
int round_half_away(double v) {
  const double a = abs(v), f = floor(a);
  const int r = int(f) + (a - f >= 0.5 ? 1 : 0);
  return v < 0.0 ? -r : r;
}

/// GradientTable::coord then ::lookup.
double table_lookup(double d_edge, bool occluded, bool edge_front, double width) {
  const double hb = P.half_band;
  precise const double dn0 = (d_edge + hb) / (2.0 * hb);
  const double dn = clamp(dn0, 0.0, 1.0 - 1e-9);
  precise const double coord = 0.25 * (dn + (occluded ? 1.0 : 0.0)) + 0.5 * (edge_front ? 1.0 : 0.0);
  precise const double c4 = clamp(coord, 0.0, 1.0 - 1e-12) * 4.0;
  const int k = min(3, int(floor(c4)));
  precise const double u = (c4 - double(k)) * double(kQuarter);
  const int m = min(kQuarter - 1, int(floor(u)));
  precise const double f = u - double(m);
  int r = 0;
  if (P.rows > 1 && P.row_width_max > 0.0) {
    precise const double row = width / P.row_width_max * double(P.rows - 1);
    r = clamp(round_half_away(row), 0, P.rows - 1);
  }
  const uint q = uint((r * 4 + k) * (kQuarter + 1) + m);
  precise const double v = (1.0 - f) * double(pc.table.v[q]) + f * double(pc.table.v[q + 1u]);
  return v;
}

double sample_at(double sx, double sy, inout double width) {
  if (P.radius == 0.0) {
    // Hard mode: the plain shadow map where the four texels the filter reads agree (§2.2).
    const int x0 = int(floor(sx - 0.5)), y0 = int(floor(sy - 0.5));
    const int nb = (blocked(x0, y0) ? 1 : 0) + (blocked(x0 + 1, y0) ? 1 : 0) +
                   (blocked(x0, y0 + 1) ? 1 : 0) + (blocked(x0 + 1, y0 + 1) ? 1 : 0);
    if (nb == 0 || nb == 4) {
      width = 0.0;
      return nb == 0 ? 1.0 : 0.0;
    }
  }
  const bool occluded = blocked(int(floor(sx)), int(floor(sy)));
  const double ze = edge_depth(sx, sy);
  precise const double zlimit = depth_ - bias_;
  const bool edge_front = ze < zlimit;
  // §2.2.1: penumbra width (texels) = (2R/(z·texel_tan))·(z/z_E − 1).
  precise const double w = 2.0 * P.radius / (depth_ * P.texel_tan) * (depth_ / ze - 1.0);
  width = edge_front && P.radius > 0.0 ? w : 0.0;
  return table_lookup(edge_distance(sx, sy), occluded, edge_front, 0.5 * width);
}

void main() {
  const uint a = global_id();
  if (a >= pc.n) return;
  P = pc.prm;
  res_ = int(P.resolution);
  float lit = 1.0;
  if (setup(dvec3(pc.points.v[2u * a].xyz), dvec3(pc.points.v[2u * a + 1u].xyz))) {
    double width = 0.0;
    double v = sample_at(sx_, sy_, width);
    if (P.radius > 0.0 && width > 0.0) {
      // §2.2.1: four samples on a circle of radius width/4 around the point.
      precise const double rr = min(0.25 * width, P.half_band);
      precise double sum = 0.0;
      double unused = 0.0;
      for (int k = 0; k < 4; ++k) {
        precise const double x = sx_ + rr * P.cos_k[k], y = sy_ + rr * P.sin_k[k];
        sum += sample_at(x, y, unused);
      }
      v = 0.25 * sum;
    }
    lit = float(clamp(v, 0.0, 1.0));
  }
  pc.vis.v[a] = lit;
}
