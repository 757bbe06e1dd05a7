// Comparing two sample-exact methods' per-sample masks on a test frame, with every mismatch
// classified: a numerical tie (the segment to the sample passes within float tolerance of a
// triangle's edge or ends on its plane) or unexplained. Shared by the GEARS, DCS and Vulkan tests.
#pragma once

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "penumbra/render/receivers.hpp"
#include "support/frame_helpers.hpp"

namespace penumbra::test {

/// Does the segment o → o + d cross alpha-textured triangle t of m within float rounding of a
/// border between texels of different sides of the alpha cutoff (nearest-texel lookups of the
/// interpolated uv: raytrace's Embree barycentrics and a method's own may pick either texel)?
inline bool near_texel_border(const Scene& scene, const Mesh& m, size_t t, const DVec3& o,
                              const DVec3& d, double tol_texels = 1e-3) {
  const Material& mat = scene.material_of(m);
  if (mat.alpha_texture < 0 || m.uvs.empty()) return false;
  const Texture& tex = scene.textures[mat.alpha_texture];
  double u = 0.0, v = 0.0;
  segment_crosses_triangle(o, d, DVec3(m.vertex(t, 0)), DVec3(m.vertex(t, 1)),
                           DVec3(m.vertex(t, 2)), &u, &v);
  const Triangle& tri = m.triangles[t];
  const DVec2 uv = (1.0 - u - v) * DVec2(m.uvs[tri.v[0]]) + u * DVec2(m.uvs[tri.v[1]]) +
                   v * DVec2(m.uvs[tri.v[2]]);
  const double size[2] = {static_cast<double>(tex.width), static_cast<double>(tex.height)};
  for (int a = 0; a < 2; ++a) {
    const double x = (uv[a] - std::floor(uv[a])) * size[a];
    if (std::abs(x - std::round(x)) <= tol_texels) return true;
  }
  return false;
}

/// Is the segment origin → x numerically ambiguous against some occluding triangle: within a
/// relative `tol` of one of its edge planes or of its plane (t = 1), or crossing an alpha texture
/// at a texel border? Double precision, brute force.
inline bool ambiguous(const Scene& scene, const DVec3& o, const DVec3& x, double tol = 1e-4) {
  const DVec3 d = x - o;
  for (const Mesh& m : scene.meshes) {
    if (!m.casts_shadows) continue;
    for (size_t t = 0; t < m.triangle_count(); ++t) {
      const DVec3 a = DVec3(m.vertex(t, 0)) - o, b = DVec3(m.vertex(t, 1)) - o,
                  c = DVec3(m.vertex(t, 2)) - o;
      const DVec3 n[3] = {glm::cross(a, b), glm::cross(b, c), glm::cross(c, a)};
      const double det = glm::dot(a, n[1]);
      if (det == 0.0) continue;
      const double s = det > 0 ? 1.0 : -1.0;
      double e[3], lo = 1e300;
      for (int i = 0; i < 3; ++i) {
        e[i] = s * glm::dot(n[i], d) / (glm::length(n[i]) * glm::length(d) + 1e-300);
        lo = std::min(lo, e[i]);
      }
      if (lo < -tol) continue;  // clearly outside the cone
      const double sum = s * glm::dot(n[0] + n[1] + n[2], d);
      const double tt = std::abs(det) / (sum != 0.0 ? sum : 1e-300);
      if (lo <= tol && tt <= 1.0 + tol && tt > 0.0) return true;  // near an edge plane
      if (lo > tol && std::abs(tt - 1.0) <= tol) return true;     // hit point at the light
      if (lo > tol && tt > 0.0 && tt < 1.0 && near_texel_border(scene, m, t, o, d)) return true;
    }
  }
  return false;
}

struct MaskAgreement {
  uint64_t pairs = 0, differ = 0, unexplained = 0;
  double mean_abs_dv = 0.0;
  int blocked = 0;
};

/// Compares the masks of two results `a` (the reference) and `b` on every active pixel of light 0;
/// classifies each mismatch.
inline MaskAgreement compare_masks(const TestFrame& t, const MethodResult& a, const MethodResult& b,
                                   bool classify = true) {
  const SampleMasks& ma = *a.per_light[0].masks;
  const SampleMasks& mb = *b.per_light[0].masks;
  const GBuffer& g = t.frame->gbuffer();
  const int n = t.frame->samples().count();
  MaskAgreement out;
  std::vector<Vec2> uv(n);
  size_t active = 0;
  for (size_t i = 0; i < g.pixel_count(); ++i) {
    if (t.frame->receivers(0)[i] != kActive) continue;
    ++active;
    out.mean_abs_dv += std::abs(a.per_light[0].lit[i] - b.per_light[0].lit[i]);
    for (int s = 0; s < n; ++s) {
      ++out.pairs;
      out.blocked += ma.blocked(i, s);
      if (ma.blocked(i, s) == mb.blocked(i, s)) continue;
      ++out.differ;
      if (!classify) continue;
      t.frame->samples().pixel_samples(static_cast<int>(i % g.width), static_cast<int>(i / g.width),
                                       uv);
      const Vec3 o = g.shadow_origin(i);
      const Vec3 x = light_frame(t.scene->lights[0], o).point(uv[s]);
      if (!ambiguous(*t.scene, DVec3(o), DVec3(x))) {
        ++out.unexplained;
        if (out.unexplained <= 5)
          std::printf("unexplained mismatch: pixel %zu sample %d %s %d %s %d\n", i, s,
                      a.method.c_str(), int(ma.blocked(i, s)), b.method.c_str(),
                      int(mb.blocked(i, s)));
      }
    }
  }
  out.mean_abs_dv /= std::max<size_t>(1, active);
  return out;
}

/// Runs `method` (with `options`) and `reference` on `t` and compares their masks.
inline MaskAgreement compare_masks(const TestFrame& t, const std::string& method,
                                   const std::map<std::string, std::string>& options = {},
                                   bool classify = true,
                                   const std::string& reference = "raytrace") {
  return compare_masks(t, t.run(reference, {}, true), t.run(method, options, true), classify);
}

/// `max_unexplained` > 0 only where a known, documented defect is pinned (the test says which).
inline void expect_equal_masks(const MaskAgreement& a, int min_blocked = 100,
                               uint64_t max_unexplained = 0) {
  std::printf(
      "masks: %llu pairs, %d blocked, %llu differ (%.5f%%), %llu unexplained, mean |dV| %.2e\n",
      static_cast<unsigned long long>(a.pairs), a.blocked,
      static_cast<unsigned long long>(a.differ), 100.0 * a.differ / std::max<uint64_t>(1, a.pairs),
      static_cast<unsigned long long>(a.unexplained), a.mean_abs_dv);
  EXPECT_GT(a.blocked, min_blocked);
  EXPECT_LE(static_cast<double>(a.differ), 1e-3 * a.pairs) << a.differ << " of " << a.pairs;
  EXPECT_LE(a.unexplained, max_unexplained)
      << "mismatches not on a triangle edge within float tolerance";
  EXPECT_LE(a.mean_abs_dv, 1e-3);
}

}  // namespace penumbra::test
