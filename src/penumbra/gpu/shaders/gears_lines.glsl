// GEARS step 4 on the GPU, shared by the row-span (gears_raster.comp) and per-sample
// (gears_samples.comp) rasterizers: the four lines of a triangle seen from a pixel and the alpha
// test at a sample, the CPU's arithmetic (shadows/gears/raster.cpp) operation for operation.
// Expects a push-constant block `pc` with `tris`, `vals`, `alpha` and `texels`.

// max/min as the CPU's vector code writes them (a NaN operand picks b).
float vmax(float a, float b) { return a > b ? a : b; }
float vmin(float a, float b) { return a < b ? a : b; }

/// Does alpha-tested triangle t block the light point (su, sv)? The texture decides at the
/// barycentrics of the sample's ray (the CPU's hit_barycentrics and Texture::texel_index).
bool alpha_blocks_at(uint t, float la[4], float lb[4], float lc[4], float su, float sv) {
  const vec4 h = pc.alpha.v[6u * t];
  const vec4 uv01 = pc.alpha.v[6u * t + 1u];
  const vec2 uv2 = pc.alpha.v[6u * t + 2u].xy;
  precise float e0 = la[0] + lb[0] * su + lc[0] * sv;  // ∝ λ_C
  precise float e1 = la[1] + lb[1] * su + lc[1] * sv;  // ∝ λ_A
  precise float e2 = la[2] + lb[2] * su + lc[2] * sv;  // ∝ λ_B
  precise float sum = e0 + e1 + e2;
  precise float bu = sum > 0.0 ? e2 / sum : 0.0, bv = sum > 0.0 ? e0 / sum : 0.0;
  precise vec2 uv = (1.0 - bu - bv) * uv01.xy + bu * uv01.zw + bv * uv2;
  const int width = int(h.y), height = int(h.z);
  const float u = uv.x - floor(uv.x), v = uv.y - floor(uv.y);
  const int tx = min(width - 1, max(0, int(u * float(width))));
  const int ty = min(height - 1, max(0, int(v * float(height))));
  return pc.texels.v[floatBitsToUint(h.x) + uint(ty * width + tx)] != 0u;
}

/// The transmittance of triangle t's material: 0 for an opaque occluder, which sets mask bits; a
/// semi-opaque one only scales the transmittance of the samples it covers.
float transmittance_of(uint t) { return pc.alpha.v[6u * t + 2u].z; }

/// Semi-opaque occluders: multiplies the transmittance stored (as float bits) at word `at`, as the
/// CPU multiplies its per-sample transmittance, one layer after another in list order.
void attenuate(Uints store, uint at, float transmittance) {
  precise float tr = uintBitsToFloat(store.v[at]) * transmittance;
  store.v[at] = floatBitsToUint(tr);
}

/// End of a pixel's depth prefix of cell list [b0, b1): the entries whose triangle's nearest depth
/// on this side (the first vertex's w) is at most `cut`. The lists are in (depth, id) order.
uint depth_prefix_end(uint b0, uint b1, float cut) {
  uint lo = b0, hi = b1;
  while (lo < hi) {
    const uint mid = lo + (hi - lo) / 2u;
    if (pc.tris.v[3u * pc.vals.v[mid]].w <= cut) lo = mid + 1u;
    else hi = mid;
  }
  return lo;
}

/// The per-pixel slab test (gears/item_cull.hpp may_block; the depth cut is the walk's prefix):
/// triangle t's slab bounds (hx0, hx1, hy0, hy1) against the pixel's own (ix0, ix1, iy0, iy1).
bool in_slabs(uint t, vec4 pixel) {
  const vec4 h = pc.alpha.v[6u * t + 3u];
  return pixel.x <= h.x && pixel.y >= h.y && pixel.z <= h.z && pixel.w >= h.w;
}

/// The CPU's separating-plane and solid tests (CandidateBatch::keep; gears/item_cull.hpp
/// TrianglePlane, gears/solids.hpp): triangle t cannot block pixel point p when p and every light
/// point lie strictly on one side of its plane, nor when it is a face of a solid that p is
/// certified outside of (`outside`: one bit per solid) and p lies strictly behind it.
bool plane_keeps(uint t, vec3 p, uvec2 outside) {
  const vec4 n = pc.alpha.v[6u * t + 4u];  // nx, ny, nz, d
  const vec4 e = pc.alpha.v[6u * t + 5u];  // |n|₁, lmin, lmax, the solid's index bits
  precise float side = n.x * p.x + n.y * p.y + n.z * p.z - n.w;
  const float p_inf = max(abs(p.x), max(abs(p.y), abs(p.z)));
  precise float tol = 1e-5 * (e.x * p_inf + vmax(n.w, -n.w));  // kPlaneRel
  const uint s = floatBitsToUint(e.w);
  const uint word = s < 32u ? outside.x : s < 64u ? outside.y : 0u;
  const bool behind_solid = ((word >> (s & 31u)) & 1u) != 0u;
  return !((side > tol && e.y > 0.0) || (side < -tol && (e.z < 0.0 || behind_solid)));
}

/// The entries [e0, e1) of a cell list [b0, b1) that dispatch `first` walks, `chunk` at most:
/// within the pixel's depth prefix (flags & 4) and, deepest first (flags & 2), counted from its
/// end. False when none are left.
bool walk_range(uint b0, uint b1, float cut, uint first, uint chunk, uint flags, out uint e0,
                out uint e1) {
  if (first >= b1 - b0) return false;
  const uint end = (flags & 4u) != 0u ? depth_prefix_end(b0, b1, cut) : b1;
  if (first >= end - b0) return false;
  if ((flags & 2u) != 0u) {
    e1 = end - first;
    e0 = e1 - min(chunk, e1 - b0);
  } else {
    e0 = b0 + first;
    e1 = e0 + min(chunk, end - e0);
  }
  return true;
}

/// The CPU's shadow-box test (shadows/gears/raster.cpp shadow_box_holds_samples), for a light
/// whose uv is light-space xy (eu = x, ev = y: rect and disk lights). When the three vertices lie
/// between the light plane and pixel point p, the triangle's shadow on the light is the triangle
/// of their projections from p, so its uv bounding box must overlap the sample box [uv_lo, uv_hi]
/// and, on a k×k grid (k > 0), hold a sample centre ((i + ½)/k, (j + ½)/k), the box widened by
/// 10⁻⁴ light widths (far above the projections' rounding, so the lines still decide every sample
/// near an edge). False when it cannot cover a sample; columns box.x … box.y and rows box.z …
/// box.w hold all it can cover (`boxed`: that box was computed; else the whole grid).
bool shadow_box(uint t, vec3 p, vec3 eu, vec3 ev, int k, vec2 uv_lo, vec2 uv_hi, out ivec4 box,
                out bool boxed) {
  box = ivec4(0, k - 1, 0, k - 1);
  boxed = false;
  if (eu != vec3(1.0, 0.0, 0.0) || ev != vec3(0.0, 1.0, 0.0)) return true;
  precise vec3 A = pc.tris.v[3u * t].xyz - p;
  precise vec3 B = pc.tris.v[3u * t + 1u].xyz - p;
  precise vec3 C = pc.tris.v[3u * t + 2u].xyz - p;
  if (!(A.z < 0.0 && A.z > -p.z && B.z < 0.0 && B.z > -p.z && C.z < 0.0 && C.z > -p.z))
    return true;
  precise float ta = p.z / -A.z, tb = p.z / -B.z, tc = p.z / -C.z;
  precise float ua = p.x + A.x * ta, ub = p.x + B.x * tb, uc = p.x + C.x * tc;
  precise float va = p.y + A.y * ta, vb = p.y + B.y * tb, vc = p.y + C.y * tc;
  const float u0 = vmin(vmin(ua, ub), uc), u1 = vmax(vmax(ua, ub), uc);
  const float v0 = vmin(vmin(va, vb), vc), v1 = vmax(vmax(va, vb), vc);
  if (!(u0 <= uv_hi.x && u1 >= uv_lo.x && v0 <= uv_hi.y && v1 >= uv_lo.y)) return false;
  if (k <= 0) return true;
  const float kf = float(k), slack = 1e-4 * kf;
  // First and last sample centre within [x0, x1]: ceil / floor of k·x − ½ ∓ slack, clamped to
  // [−2, k + 1] first (NaN → −2).
  precise float a0 = kf * u0 - 0.5 - slack, a1 = kf * u1 - 0.5 + slack;
  precise float b0 = kf * v0 - 0.5 - slack, b1 = kf * v1 - 0.5 + slack;
  const int i0 = max(int(ceil(vmin(vmax(a0, -2.0), kf + 1.0))), 0);
  const int i1 = min(int(floor(vmin(vmax(a1, -2.0), kf + 1.0))), k - 1);
  const int j0 = max(int(ceil(vmin(vmax(b0, -2.0), kf + 1.0))), 0);
  const int j1 = min(int(floor(vmin(vmax(b1, -2.0), kf + 1.0))), k - 1);
  box = ivec4(i0, i1, j0, j1);
  boxed = true;
  return i0 <= i1 && j0 <= j1;
}

/// u × w with u, w in lexicographic order; `sgn` = +1 when that order is (u, w), else −1.
vec3 edge_normal(vec3 u, vec3 w, out float sgn) {
  const bool before = u.x < w.x || (u.x == w.x && (u.y < w.y || (u.y == w.y && u.z <= w.z)));
  const vec3 p0 = before ? u : w, p1 = before ? w : u;
  sgn = before ? 1.0 : -1.0;
  precise vec3 r = vec3(p0.y * p1.z - p0.z * p1.y, p0.z * p1.x - p0.x * p1.z,
                        p0.x * p1.y - p0.y * p1.x);
  return r;
}

/// The four lines of triangle t seen from pixel point p (light point X(u, v) = p + w + u·eu + v·ev):
/// t blocks (u, v) iff la[m] + lb[m]·u + lc[m]·v ≥ 0 for m = 0..3 (shadows/gears/raster.hpp
/// LineBatch). False when no point of the sample box [uv_lo, uv_hi] can pass all four.
bool triangle_lines(uint t, vec3 p, vec3 w, vec3 eu, vec3 ev, vec2 uv_lo, vec2 uv_hi,
                    out float out_a[4], out float out_b[4], out float out_c[4]) {
  precise vec3 A = pc.tris.v[3u * t].xyz - p;
  precise vec3 B = pc.tris.v[3u * t + 1u].xyz - p;
  precise vec3 C = pc.tris.v[3u * t + 2u].xyz - p;
  // Edge-plane normals n0 = a×b, n1 = b×c, n2 = c×a, each from its two vertices in a canonical
  // (lexicographic) order and then signed for this triangle, so that two triangles sharing an
  // edge get exactly opposite lines (watertight, as on the CPU).
  precise vec3 n[3];
  float sgn[3];
  n[0] = edge_normal(A, B, sgn[0]);
  n[1] = edge_normal(B, C, sgn[1]);
  n[2] = edge_normal(C, A, sgn[2]);
  precise float det = sgn[1] * (A.x * n[1].x + A.y * n[1].y + A.z * n[1].z);
  if (det == 0.0) return false;
  const float s = det > 0.0 ? 1.0 : -1.0;
  precise float la[4], lb[4], lc[4];
  [[unroll]] for (int m = 0; m < 3; ++m) {
    const float sm = s * sgn[m];
    la[m] = sm * (n[m].x * w.x + n[m].y * w.y + n[m].z * w.z);
    lb[m] = sm * (n[m].x * eu.x + n[m].y * eu.y + n[m].z * eu.z);
    lc[m] = sm * (n[m].x * ev.x + n[m].y * ev.y + n[m].z * ev.z);
  }
  // The plane: the segment reaches the triangle (t ≤ 1) iff Σ s·e_i(X) ≥ |det|.
  la[3] = la[0] + la[1] + la[2] - s * det;
  lb[3] = lb[0] + lb[1] + lb[2];
  lc[3] = lc[0] + lc[1] + lc[2];
  // Can every line be non-negative somewhere in the samples' bounding box?
  [[unroll]] for (int m = 0; m < 4; ++m) {
    precise float best = la[m] + vmax(lb[m] * uv_lo.x, lb[m] * uv_hi.x) +
                         vmax(lc[m] * uv_lo.y, lc[m] * uv_hi.y);
    if (!(best >= 0.0)) return false;
  }
  out_a = la;
  out_b = lb;
  out_c = lc;
  return true;
}
