#include "penumbra/pipeline/irradiance.hpp"

#include <algorithm>
#include <cmath>

#include "penumbra/core/parallel.hpp"
#include "penumbra/core/simd.hpp"
#include "penumbra/render/receivers.hpp"

#if PENUMBRA_HAVE_LIBMVEC && defined(__x86_64__)
#include <immintrin.h>
// glibc's vector atan2 (libmvec, x86-64 vector ABI names): within 4 ulp of the scalar atan2.
extern "C" __m256d _ZGVdN4vv_atan2(__m256d y, __m256d x);
#endif

namespace penumbra {

namespace {

constexpr int kLanes = 8;  // receivers per batch of fill's rectangle path

#if PENUMBRA_HAVE_LIBMVEC && defined(__x86_64__)
/// libmvec's AVX2 atan2, 4 lanes at a time (called only where simd::at_least_avx2()).
__attribute__((target("avx2,fma"))) void atan2_lanes_avx2(const double* y, const double* x,
                                                          double* out) {
  for (int h = 0; h < kLanes; h += 4)
    _mm256_storeu_pd(out + h, _ZGVdN4vv_atan2(_mm256_loadu_pd(y + h), _mm256_loadu_pd(x + h)));
}
#endif

/// out[l] = atan2(y[l], x[l]) for the kLanes lanes.
void atan2_lanes(const double* y, const double* x, double* out, bool avx2) {
#if PENUMBRA_HAVE_LIBMVEC && defined(__x86_64__)
  if (avx2) return atan2_lanes_avx2(y, x, out);
#endif
  (void)avx2;
  for (int l = 0; l < kLanes; ++l) out[l] = std::atan2(y[l], x[l]);
}

/// The contour term of the straight edge a → b (both relative to the receiver): θ · (n·û).
double edge_term(const DVec3& a, const DVec3& b, const DVec3& n) {
  const DVec3 c = glm::cross(a, b);
  const double len = glm::length(c);
  if (!(len > 0.0)) return 0.0;
  return std::atan2(len, glm::dot(a, b)) * glm::dot(n, c) / len;
}

/// ∮ n·(x × dx)/|x|² over the convex polygon x[0..count) (relative to the receiver) clipped to
/// n·x > 0, signed by the polygon's orientation. Streams the edges (Sutherland–Hodgman without a
/// buffer): a convex polygon leaves the hemisphere at most once and re-enters at most once, and
/// the horizon chord from the exit to the entry point closes the clipped outline.
double clipped_contour(const DVec3* x, int count, const DVec3& n) {
  double sum = 0.0;
  DVec3 exit(0.0), entry(0.0);
  bool crossed = false;
  for (int i = 0; i < count; ++i) {
    const DVec3& a = x[i];
    const DVec3& b = x[(i + 1) % count];
    const double ha = glm::dot(n, a), hb = glm::dot(n, b);
    if (ha > 0.0 && hb > 0.0) {
      sum += edge_term(a, b, n);
    } else if (ha > 0.0) {
      exit = a + (ha / (ha - hb)) * (b - a);
      sum += edge_term(a, exit, n);
      crossed = true;
    } else if (hb > 0.0) {
      entry = a + (ha / (ha - hb)) * (b - a);
      sum += edge_term(entry, b, n);
      crossed = true;
    }
  }
  if (crossed) sum += edge_term(exit, entry, n);
  return sum;
}

/// +½ or −½: the factor that turns the signed contour of an outline ordered counter-clockwise about
/// `outline_normal` into P ≥ 0 as seen from `to_receiver` (the outline's point minus p, negated).
double orientation(const DVec3& outline_normal, const DVec3& from_outline_to_receiver) {
  return glm::dot(outline_normal, from_outline_to_receiver) > 0.0 ? -0.5 : 0.5;
}

/// atan(y)/y and log1p(x)/x, continuous at 0: they keep the small-ρ limits of the disk's closed
/// form free of cancellation.
double atan_ratio(double y) {
  return std::abs(y) < 1e-8 ? 1.0 - y * y / 3.0 : std::atan(y) / y;
}
double log1p_ratio(double x) {
  return std::abs(x) < 1e-8 ? 1.0 - 0.5 * x : std::log1p(x) / x;
}

/// ∫_{τ0}^{τ1} (A + B cos τ + C sin τ) / (D + ρ cos τ) dτ for D > ρ ≥ 0 and τ1 − τ0 ≤ 2π, in a form
/// that stays accurate as ρ → 0 (a receiver near the disk's axis). With s = √(D² − ρ²) and
/// k = √((D − ρ)/(D + ρ)), an antiderivative of 1/(D + ρ cos τ) is (2/s)·atan(k·tan(τ/2)), written
/// continuously for all τ as (2/s)·(τ/2 + g(τ)), g(τ) = atan((k − 1)·sin τ / ((1 + k) + (1 − k)·cos
/// τ)) = O(ρ). Then ∫ cos/den = (Δ − D·∫1/den)/ρ and ∫ sin/den = −ln(den(τ1)/den(τ0))/ρ, both with
/// the 1/ρ divided out analytically.
double rational_arc_integral(double tau0, double tau1, double A, double B, double C, double D,
                             double rho) {
  const double s = std::sqrt((D - rho) * (D + rho));
  const double sp = std::sqrt(D + rho), sm = std::sqrt(D - rho);
  const double k = sm / sp;
  const double kappa = -2.0 / (sp * (sm + sp));  // (k − 1)/ρ
  const auto g_over_rho = [&](double tau) {
    const double w = std::sin(tau) / ((1.0 + k) + (1.0 - k) * std::cos(tau));
    return kappa * w * atan_ratio(rho * kappa * w);
  };
  const double delta = tau1 - tau0;
  const double dg = g_over_rho(tau1) - g_over_rho(tau0);  // (g(τ1) − g(τ0)) / ρ
  const double J = delta / s + 2.0 / s * rho * dg;
  const double K = -delta * rho / (s * (s + D)) - 2.0 * D / s * dg;
  const double den0 = D + rho * std::cos(tau0);
  const double dcos = std::cos(tau1) - std::cos(tau0);
  const double L = -dcos / den0 * log1p_ratio(rho * dcos / den0);
  return A * J + B * K + C * L;
}

}  // namespace

double polygon_projected_solid_angle(const DVec3& p, const DVec3& n, const DVec3* corners,
                                     int count) {
  DVec3 x[8];
  count = std::min(count, 8);
  for (int i = 0; i < count; ++i) x[i] = corners[i] - p;
  return 0.5 * std::abs(clipped_contour(x, count, n));
}

double disk_projected_solid_angle(const DVec3& p, const DVec3& n, const DVec3& center,
                                  const DVec3& axis_u, const DVec3& axis_v, double radius) {
  const DVec3 q = center - p;
  const double r = radius;
  // Height above the horizon along the rim: H0 + H1 cos t + H2 sin t.
  const double h0 = glm::dot(n, q), h1 = r * glm::dot(n, axis_u), h2 = r * glm::dot(n, axis_v);
  const double h_amp = std::hypot(h1, h2);
  if (!(r > 0.0) || h0 <= -h_amp) return 0.0;  // wholly below the horizon (or empty)

  const double A = r * r * glm::dot(n, glm::cross(axis_u, axis_v));
  const double B = r * glm::dot(n, glm::cross(q, axis_v));
  const double C = -r * glm::dot(n, glm::cross(q, axis_u));
  const double D = glm::dot(q, q) + r * r;
  const double E = 2.0 * r * glm::dot(q, axis_u);
  const double F = 2.0 * r * glm::dot(q, axis_v);
  const double rho = std::hypot(E, F);
  if (!(D - rho > 1e-12 * D)) {
    // The receiver lies on the rim (|x(t)| = 0 somewhere): the closed form's ∫dt/den diverges
    // while P does not. A 4096-gon is within 1e-6 relative of the circle; this set has measure
    // zero, so its cost does not matter.
    constexpr int kRim = 4096;
    double sum = 0.0;
    DVec3 prev = q + r * axis_u;
    for (int i = 1; i <= kRim; ++i) {
      const double t = 2.0 * kPi * i / kRim;
      const DVec3 cur = q + r * (std::cos(t) * axis_u + std::sin(t) * axis_v);
      const DVec3 quad[3] = {q, prev, cur};
      sum += clipped_contour(quad, 3, n);
      prev = cur;
    }
    return 0.5 * std::abs(sum);
  }
  // Rotate t by φ = atan2(F, E) so that the denominator reads D + ρ cos τ.
  const double c_phi = rho > 0.0 ? E / rho : 1.0, s_phi = rho > 0.0 ? F / rho : 0.0;
  const double phi = std::atan2(s_phi, c_phi);
  const double B_rot = B * c_phi + C * s_phi, C_rot = -B * s_phi + C * c_phi;
  if (h0 >= h_amp)  // wholly above the horizon: the full period
    return 0.5 * std::abs(rational_arc_integral(-kPi, kPi, A, B_rot, C_rot, D, rho));
  // The arc above the horizon, cos(t − ψ) > −H0 / |H|, then the chord back along the horizon.
  const double psi = std::atan2(h2, h1);
  const double delta = std::acos(std::clamp(-h0 / h_amp, -1.0, 1.0));
  const double t0 = psi - delta, t1 = psi + delta;
  const auto rim = [&](double t) { return q + r * (std::cos(t) * axis_u + std::sin(t) * axis_v); };
  const double arc = rational_arc_integral(t0 - phi, t1 - phi, A, B_rot, C_rot, D, rho);
  return 0.5 * std::abs(arc + edge_term(rim(t1), rim(t0), n));
}

LightIrradiance::LightIrradiance(const Scene& scene, const Light& light) : light_(&light) {
  if (light.shape == LightShape::rect) {
    const LightFrame f = light_frame(light, light.center);  // a rectangle's frame is fixed
    const DVec3 corner(f.corner), edge_u(f.edge_u), edge_v(f.edge_v);
    rect_corners_[0] = corner;
    rect_corners_[1] = corner + edge_u;
    rect_corners_[2] = corner + edge_u + edge_v;
    rect_corners_[3] = corner + edge_v;
    rect_emit_ = DVec3(f.emit_normal);
  }
  if (!light.is_textured() || light.shape != LightShape::rect) return;
  const Texture& tex = scene.textures[light.emission_texture];
  blocks_u_ = std::min(tex.width, kMaxIrradianceBlocksPerSide);
  blocks_v_ = std::min(tex.height, kMaxIrradianceBlocksPerSide);
  // Overlap (in uv) of block b with texel t along one axis: the area weights of the block means.
  const auto overlap = [](int b, int blocks, int t, int texels) {
    const double lo = std::max(static_cast<double>(b) / blocks, static_cast<double>(t) / texels);
    const double hi =
        std::min(static_cast<double>(b + 1) / blocks, static_cast<double>(t + 1) / texels);
    return std::max(0.0, hi - lo);
  };
  block_radiance_.assign(static_cast<size_t>(blocks_u_) * blocks_v_, DVec3(0.0));
  const double block_area = 1.0 / (static_cast<double>(blocks_u_) * blocks_v_);
  for (int ty = 0; ty < tex.height; ++ty)
    for (int tx = 0; tx < tex.width; ++tx) {
      const Vec3 rgb = tex.sample_rgb(Vec2((tx + 0.5f) / static_cast<float>(tex.width),
                                           (ty + 0.5f) / static_cast<float>(tex.height)));
      const DVec3 texel = DVec3(light.radiance) * DVec3(rgb);
      const int bx = tx * blocks_u_ / tex.width, by = ty * blocks_v_ / tex.height;
      // A texel overlaps at most two blocks per axis (blocks are at least a texel wide).
      for (int j = by; j <= std::min(by + 1, blocks_v_ - 1); ++j)
        for (int i = bx; i <= std::min(bx + 1, blocks_u_ - 1); ++i) {
          const double w = overlap(i, blocks_u_, tx, tex.width) *
                           overlap(j, blocks_v_, ty, tex.height) / block_area;
          block_radiance_[static_cast<size_t>(j) * blocks_u_ + i] += w * texel;
        }
    }
}

Vec3 LightIrradiance::at(const Vec3& receiver, const Vec3& normal) const {
  const Light& light = *light_;
  if (light.shape == LightShape::point) {
    const Vec3 d = light.center - receiver;
    const float r2 = glm::dot(d, d);
    const float cos_r = glm::dot(normal, d) / std::sqrt(r2);
    return cos_r > 0.0f ? light.radiance * (cos_r / r2) : Vec3(0.0f);
  }
  const LightFrame f = light_frame(light, receiver);
  const DVec3 p(receiver), n(normal);
  const DVec3 corner(f.corner), edge_u(f.edge_u), edge_v(f.edge_v), emit(f.emit_normal);
  // One-sided lights emit toward emit_normal only; a sphere's silhouette disk always faces p.
  const bool one_sided = !light.two_sided && light.shape != LightShape::sphere;
  if (one_sided && !(glm::dot(emit, p - corner) > 0.0)) return Vec3(0.0f);
  if (light.shape == LightShape::rect) {
    if (!block_radiance_.empty()) return textured_at(p, n, f);
    const DVec3 quad[4] = {corner, corner + edge_u, corner + edge_u + edge_v, corner + edge_v};
    return light.radiance * static_cast<float>(polygon_projected_solid_angle(p, n, quad, 4));
  }
  const double radius = 0.5 * glm::length(edge_u);
  const double solid =
      disk_projected_solid_angle(p, n, corner + 0.5 * (edge_u + edge_v), glm::normalize(edge_u),
                                 glm::normalize(edge_v), radius);
  return light.radiance * static_cast<float>(solid);
}

Vec3 LightIrradiance::textured_at(const DVec3& p, const DVec3& n, const LightFrame& f) const {
  const int bu = blocks_u_, bv = blocks_v_, row = bu + 1;
  // The block grid's corners relative to p, and the contour term of every grid edge that lies
  // wholly above the horizon: each is shared by two blocks, so it is computed once.
  thread_local std::vector<DVec3> x;
  thread_local std::vector<double> along_u, along_v;
  x.resize(static_cast<size_t>(row) * (bv + 1));
  along_u.assign(static_cast<size_t>(bu) * (bv + 1), 0.0);
  along_v.assign(static_cast<size_t>(row) * bv, 0.0);
  const DVec3 corner = DVec3(f.corner) - p, edge_u(f.edge_u), edge_v(f.edge_v);
  for (int j = 0; j <= bv; ++j)
    for (int i = 0; i <= bu; ++i)
      x[static_cast<size_t>(j) * row + i] =
          corner + (static_cast<double>(i) / bu) * edge_u + (static_cast<double>(j) / bv) * edge_v;
  const auto above = [&](size_t k) { return glm::dot(n, x[k]) > 0.0; };
  for (int j = 0; j <= bv; ++j)
    for (int i = 0; i < bu; ++i) {
      const size_t k = static_cast<size_t>(j) * row + i;
      if (above(k) && above(k + 1))
        along_u[static_cast<size_t>(j) * bu + i] = edge_term(x[k], x[k + 1], n);
    }
  for (int j = 0; j < bv; ++j)
    for (int i = 0; i <= bu; ++i) {
      const size_t k = static_cast<size_t>(j) * row + i;
      if (above(k) && above(k + row))
        along_v[static_cast<size_t>(j) * row + i] = edge_term(x[k], x[k + row], n);
    }
  const double sign = orientation(glm::cross(edge_u, edge_v), -corner);
  DVec3 sum(0.0);
  for (int j = 0; j < bv; ++j)
    for (int i = 0; i < bu; ++i) {
      const size_t k = static_cast<size_t>(j) * row + i;
      const DVec3 block[4] = {x[k], x[k + 1], x[k + 1 + row], x[k + row]};
      const int up = above(k) + above(k + 1) + above(k + 1 + row) + above(k + row);
      if (up == 0) continue;
      double contour = 0.0;
      if (up == 4) {
        contour = along_u[static_cast<size_t>(j) * bu + i] +
                  along_v[static_cast<size_t>(j) * row + i + 1] -
                  along_u[static_cast<size_t>(j + 1) * bu + i] -
                  along_v[static_cast<size_t>(j) * row + i];
      } else {
        contour = clipped_contour(block, 4, n);
      }
      sum += std::max(0.0, sign * contour) * block_radiance_[static_cast<size_t>(j) * bu + i];
    }
  return Vec3(sum);
}

void LightIrradiance::fill(const GBuffer& g, const Image<uint8_t>& classes,
                           Image<Vec3>& out) const {
  parallel_rows(g.height, [&](int y) { fill_row(g, classes, out, y); });
}

void LightIrradiance::fill_row(const GBuffer& g, const Image<uint8_t>& classes, Image<Vec3>& out,
                               int y) const {
  const bool batched = light_->shape == LightShape::rect && block_radiance_.empty();
  size_t batch[kLanes];
  int count = 0;
  for (int x = 0; x < g.width; ++x) {
    const size_t i = static_cast<size_t>(y) * g.width + x;
    if (classes[i] != kActive) continue;
    if (!batched) {
      out[i] = at(g.shadow_origin(i), g.shading_normal[i]);
      continue;
    }
    batch[count++] = i;
    if (count == kLanes) {
      fill_rect_batch(g, batch, count, out);
      count = 0;
    }
  }
  if (count > 0) fill_rect_batch(g, batch, count, out);
}

void LightIrradiance::fill_rect_batch(const GBuffer& g, const size_t* pixels, int count,
                                      Image<Vec3>& out) const {
  // Structure of arrays over the lanes (a short batch repeats its last receiver), in the same
  // operations as at() → polygon_projected_solid_angle → clipped_contour → edge_term, so that
  // only the atan2 differs; lanes where the rectangle is not wholly above the horizon, or the
  // receiver is behind a one-sided light, go through at() itself.
  alignas(64) double p[3][kLanes], n[3][kLanes];
  for (int l = 0; l < kLanes; ++l) {
    const size_t i = pixels[std::min(l, count - 1)];
    const Vec3 origin = g.shadow_origin(i), normal = g.shading_normal[i];
    for (int c = 0; c < 3; ++c) {
      p[c][l] = origin[c];
      n[c][l] = normal[c];
    }
  }
  const bool one_sided = !light_->two_sided;
  const bool avx2 = simd::at_least_avx2();
  alignas(64) double corner[4][3][kLanes], height[4][kLanes];
  bool simple[kLanes];
  for (int l = 0; l < kLanes; ++l) {
    const DVec3 to_p(p[0][l] - rect_corners_[0].x, p[1][l] - rect_corners_[0].y,
                     p[2][l] - rect_corners_[0].z);
    simple[l] = !one_sided || glm::dot(rect_emit_, to_p) > 0.0;
  }
  for (int k = 0; k < 4; ++k)
    for (int l = 0; l < kLanes; ++l) {
      for (int c = 0; c < 3; ++c) corner[k][c][l] = rect_corners_[k][c] - p[c][l];
      height[k][l] =
          n[0][l] * corner[k][0][l] + n[1][l] * corner[k][1][l] + n[2][l] * corner[k][2][l];
    }
  for (int l = 0; l < kLanes; ++l)
    simple[l] = simple[l] && height[0][l] > 0.0 && height[1][l] > 0.0 && height[2][l] > 0.0 &&
                height[3][l] > 0.0;

  alignas(64) double sum[kLanes] = {};
  for (int k = 0; k < 4; ++k) {
    const double(&a)[3][kLanes] = corner[k];
    const double(&b)[3][kLanes] = corner[(k + 1) % 4];
    alignas(64) double len[kLanes], cos_part[kLanes], n_dot_c[kLanes], angle[kLanes];
    for (int l = 0; l < kLanes; ++l) {
      // glm::cross, glm::length and glm::dot, written out per lane.
      const double cx = a[1][l] * b[2][l] - b[1][l] * a[2][l];
      const double cy = a[2][l] * b[0][l] - b[2][l] * a[0][l];
      const double cz = a[0][l] * b[1][l] - b[0][l] * a[1][l];
      len[l] = std::sqrt(cx * cx + cy * cy + cz * cz);
      cos_part[l] = a[0][l] * b[0][l] + a[1][l] * b[1][l] + a[2][l] * b[2][l];
      n_dot_c[l] = n[0][l] * cx + n[1][l] * cy + n[2][l] * cz;
    }
    atan2_lanes(len, cos_part, angle, avx2);
    for (int l = 0; l < kLanes; ++l) sum[l] += len[l] > 0.0 ? angle[l] * n_dot_c[l] / len[l] : 0.0;
  }
  for (int l = 0; l < count; ++l) {
    const size_t i = pixels[l];
    out[i] = simple[l] ? light_->radiance * static_cast<float>(0.5 * std::abs(sum[l]))
                       : at(g.shadow_origin(i), g.shading_normal[i]);
  }
}

}  // namespace penumbra
