// The per-sample loop of the soft textured shadow volumes (wedges/stsv_lookup.hpp).
//
// GCC vectorises the loop (the selects before the division and the texel fetch, a gather) only
// without -ftrapping-math; nothing here reads floating-point exception flags, so this file turns it
// off (about 2× on `dcs` over `fence`).
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC optimize("no-trapping-math")
#endif

#include "penumbra/shadows/wedges/stsv_lookup.hpp"

namespace penumbra::stsv {

int blocked_samples(const Pair& pr, const STriangle& t, const float* __restrict u,
                    const float* __restrict v, int n, uint8_t* __restrict blocked) {
  const float ax = pr.a[0], bx = pr.b[0], cx = pr.c[0];
  const float ay = pr.a[1], by = pr.b[1], cy = pr.c[1];
  const float az = pr.a[2], bz = pr.b[2], cz = pr.c[2];
  const float zmin = kMinInverseT;
  const Vec2 uv0 = t.uv[0], uv1 = t.uv[1], uv2 = t.uv[2];
  const Texture& alpha = *t.alpha;
  const float* __restrict texels = alpha.texels.data();
  const int channels = alpha.channels, width = alpha.width;
  int crossing = 0;
  for (int s = 0; s < n; ++s) {
    const float hx = ax * u[s] + bx * v[s] + cx;
    const float hy = ay * u[s] + by * v[s] + cy;
    const float hz = az * u[s] + bz * v[s] + cz;
    // Inside the triangle, strictly before the light end [App. 5.A, the RET].
    const bool in = (hx >= 0.0f) & (hy >= 0.0f) & (hz - hx - hy >= 0.0f) & (hz >= zmin);
    // Samples outside look up a finite uv (masked out below).
    const float inv = 1.0f / (in ? hz : 1.0f);
    const float b1 = (in ? hx : 0.0f) * inv, b2 = (in ? hy : 0.0f) * inv;
    // Mesh::uv_at's interpolation (eq. 5.5's S) and Texture::sample_scalar's texel.
    const Vec2 uv = (1.0f - b1 - b2) * uv0 + b1 * uv1 + b2 * uv2;
    int tx = 0, ty = 0;
    alpha.texel_index(uv, tx, ty);
    const float a = texels[(static_cast<size_t>(ty) * width + tx) * channels];
    blocked[s] = in & (a >= kAlphaCutoff);
    crossing += in;
  }
  return crossing;
}

}  // namespace penumbra::stsv
