// Depth complexity sampling on the GPU [Forest 2008 ch. 4]: the data dcs_vk.cpp uploads and the
// per-receiver geometry of shadows/wedges/dcs.cpp in double, operation for operation (`precise`:
// no contraction), so a pixel's covered regions and counter steps are the CPU's exactly:
// the edge's weight for the receiver (dcs_edges.hpp multiplicity_for), the wedge test
// (geometry.hpp Wedge::contains), the clip of the projected edge to the light square and disk
// (coverage.cpp), the covered region (dcs_counters.cpp covered_region) and its float test
// (apply_region).
#extension GL_EXT_shader_explicit_arithmetic_types_float64 : require

layout(buffer_reference, scalar) buffer Ints { int v[]; };
layout(buffer_reference, scalar) buffer Vec2s { vec2 v[]; };

const int kMaxWedgePlanes = 16;
const double kMinW = 1e-9;  // exact/projection.hpp

/// geometry.hpp Wedge: the planes (n, d), the edge, the plane tolerance, and which edge it is.
struct Wedge {
  dvec4 planes[kMaxWedgePlanes];
  dvec3 e0, e1;
  double tolerance;
  int plane_count;
  uint edge;
};
layout(buffer_reference, scalar) buffer Wedges { Wedge v[]; };

/// dcs_edges.hpp Edge and EdgeFace.
struct Edge {
  int centre_multiplicity;
  uint face_begin, face_count, layer_class;
};
layout(buffer_reference, scalar) buffer Edges { Edge v[]; };
struct Face {
  dvec3 n;
  double d;
  int sign_, pad;
};
layout(buffer_reference, scalar) buffer Faces { Face v[]; };

/// One active pixel: its shadow origin p, the light projection seen from it
/// (exact/projection.hpp LightProjection: U = dot(x − p, to_u), ...), its light frame, its screen
/// tile, and flags
/// (kValid: the projection exists; kRound: a disk's inscribed circle; kTauNeg: τ = −1).
struct Pixel {
  dvec3 p, to_u, to_v, to_w;
  dvec3 corner, edge_u, edge_v;  // its light frame (LightFrame of scene/light.hpp, in double)
  uint tile, flags;
};
layout(buffer_reference, scalar) buffer Pixels { Pixel v[]; };
const uint kValid = 1u, kRound = 2u, kTauNeg = 4u;

precise double dot3(dvec3 a, dvec3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
precise double cross2(dvec2 x, dvec2 y) { return x.x * y.y - x.y * y.x; }

/// Liang–Barsky step for f(t) = fa + t·(fb − fa) ≥ 0 on t ∈ [t0, t1] (coverage.cpp clip_linear).
bool clip_linear(double fa, double fb, inout double t0, inout double t1) {
  if (fa >= 0.0 && fb >= 0.0) return true;
  if (fa < 0.0 && fb < 0.0) return false;
  precise const double t = fa / (fa - fb);
  if (fa < 0.0)
    t0 = max(t0, t);
  else
    t1 = min(t1, t);
  return t0 <= t1;
}

/// coverage.cpp clip_edge_to_light_square on the homogeneous end points A, B.
bool clip_square(dvec3 A, dvec3 B, out dvec2 a, out dvec2 b) {
  a = dvec2(0.0), b = dvec2(0.0);
  double t0 = 0.0, t1 = 1.0;
  precise const double am = A.z - kMinW, bm = B.z - kMinW;
  if (!clip_linear(am, bm, t0, t1)) return false;
  precise const double a1 = 1.0 - A.z, b1 = 1.0 - B.z;
  if (!clip_linear(a1, b1, t0, t1)) return false;
  if (!clip_linear(A.x, B.x, t0, t1)) return false;
  precise const double ax = A.z - A.x, bx = B.z - B.x;
  if (!clip_linear(ax, bx, t0, t1)) return false;
  if (!clip_linear(A.y, B.y, t0, t1)) return false;
  precise const double ay = A.z - A.y, by = B.z - B.y;
  if (!clip_linear(ay, by, t0, t1)) return false;
  if (!(t0 < t1)) return false;
  precise const dvec3 d = B - A;
  precise const dvec3 P = t0 == 0.0 ? A : A + t0 * d;
  precise const dvec3 Q = t1 == 1.0 ? B : A + t1 * d;
  precise const dvec2 pa = dvec2(P.x / P.z, P.y / P.z);
  precise const dvec2 pb = dvec2(Q.x / Q.z, Q.y / Q.z);
  a = clamp(pa, 0.0, 1.0);
  b = clamp(pb, 0.0, 1.0);
  return true;
}

/// coverage.cpp clip_edge_to_light_disk.
bool clip_disk(inout dvec2 a, inout dvec2 b) {
  precise const dvec2 d = b - a, f = a - dvec2(0.5);
  precise const double qa = d.x * d.x + d.y * d.y;
  precise const double qb = 2.0 * (f.x * d.x + f.y * d.y);
  precise const double qc = (f.x * f.x + f.y * f.y) - 0.25;
  if (!(qa > 0.0)) return false;
  precise const double disc = qb * qb - 4.0 * qa * qc;
  if (!(disc > 0.0)) return false;
  precise const double s = sqrt(disc);
  precise const double r0 = (-qb - s) / (2.0 * qa), r1 = (-qb + s) / (2.0 * qa);
  const double t0 = max(0.0, r0), t1 = min(1.0, r1);
  if (!(t0 < t1)) return false;
  precise const dvec2 na = a + t0 * d, nb = a + t1 * d;
  a = na;
  b = nb;
  return true;
}

/// dcs_counters.hpp CoveredRegion: h_k(s) = a_k·u + b_k·v + c_k in float, the closed flags of the
/// two rays, and the v extent (band range).
struct Region {
  vec3 a, b, c;
  bool closed0, closed1;
  double v_lo, v_hi;
};

/// h(s) = sign · cross(dir, s − origin) as affine coefficients (dcs_counters.cpp half_plane).
void half_plane(inout Region r, int k, dvec2 origin, dvec2 dir, double sg) {
  precise const double a = -sg * dir.y, b = sg * dir.x;
  precise const double c = -(a * origin.x + b * origin.y);
  r.a[k] = float(a);
  r.b[k] = float(b);
  r.c[k] = float(c);
}

/// dcs_counters.cpp sector_v_range.
void sector_v_range(dvec2 c, dvec2 a, dvec2 b, double sg, inout Region r) {
  double lo = min(a.y, b.y), hi = max(a.y, b.y);
  for (int i = 0; i < 2; ++i) {
    const dvec2 p = i == 0 ? a : b;
    precise const dvec2 d = p - c;
    const double m = max(abs(d.x), abs(d.y));
    if (m > 0.0) {
      precise const double y = c.y + 0.5 / m * d.y;
      lo = min(lo, y), hi = max(hi, y);
    }
  }
  for (int i = 0; i < 4; ++i) {
    const dvec2 corner = dvec2(double(i & 1), double(i >> 1));
    precise const double s0 = sg * cross2(a - c, corner - c);
    precise const double s1 = sg * cross2(corner - c, b - c);
    if (s0 >= 0.0 && s1 >= 0.0) lo = min(lo, corner.y), hi = max(hi, corner.y);
  }
  r.v_lo = max(0.0, lo);
  r.v_hi = min(1.0, hi);
}

/// dcs_counters.cpp covered_region; `turn` the side the count changes with.
bool covered_region(dvec2 a, dvec2 b, out Region r, out int turn) {
  r.a = vec3(0.0), r.b = vec3(0.0), r.c = vec3(0.0);
  r.closed0 = true, r.closed1 = true;
  r.v_lo = 0.0, r.v_hi = 1.0;
  turn = 0;
  const dvec2 c = dvec2(0.5);
  precise const double o = cross2(a - c, b - c);
  if (o != 0.0) {
    const double sg = o > 0.0 ? 1.0 : -1.0;
    precise const dvec2 ca = a - c, cb = c - b, ab = b - a;
    half_plane(r, 0, c, ca, sg);
    half_plane(r, 1, c, cb, sg);
    half_plane(r, 2, a, ab, sg);
    sector_v_range(c, a, b, sg, r);
    r.closed0 = sg > 0.0;
    r.closed1 = sg < 0.0;
    turn = o > 0.0 ? 1 : -1;
    return true;
  }
  // c on the line ab [Forest 2008 §4.4.3]: a half-plane if c lies inside the segment.
  precise const double along = (a.x - c.x) * (b.x - c.x) + (a.y - c.y) * (b.y - c.y);
  if (!(along < 0.0)) return false;
  precise const dvec2 ab = b - a;
  double side = cross2(ab, dvec2(0.6180339887498949, 1.0));
  if (side == 0.0) side = cross2(ab, dvec2(1.0, 0.0));
  const double sg = side > 0.0 ? 1.0 : -1.0;
  r.a.xy = vec2(0.0), r.b.xy = vec2(0.0), r.c.xy = vec2(1.0);  // always true
  half_plane(r, 2, a, ab, sg);
  turn = side > 0.0 ? 1 : -1;
  return true;
}

/// dcs_counters.hpp apply_region's per-sample test.
bool covers(Region r, vec2 s) {
  precise const float h0 = r.a[0] * s.x + r.b[0] * s.y + r.c[0];
  precise const float h1 = r.a[1] * s.x + r.b[1] * s.y + r.c[1];
  precise const float h2 = r.a[2] * s.x + r.b[2] * s.y + r.c[2];
  const bool in0 = h0 > 0.0 || (h0 == 0.0 && r.closed0);
  const bool in1 = h1 > 0.0 || (h1 == 0.0 && r.closed1);
  return in0 && in1 && h2 < 0.0;
}

/// dcs_counters.hpp SampleSet::range: the band range [first, last) holding [v_lo, v_hi], in the
/// band starts from `base` on (a pixel's own set under a per-pixel pattern).
void band_range(Ints band_begin, uint base, int k, double v_lo, double v_hi, out int first,
                out int last) {
  const double m = 1e-5;
  precise const double f0 = (v_lo - m) * double(k), f1 = (v_hi + m) * double(k);
  const int b0 = clamp(int(floor(f0)), 0, k - 1);
  const int b1 = clamp(int(floor(f1)), 0, k - 1);
  first = band_begin.v[base + uint(b0)];
  last = band_begin.v[base + uint(b1 + 1)];
}
