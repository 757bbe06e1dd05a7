// Light-space pieces of `ssm` [Atty 2006 §3]: the light rectangle, the maps rendered from its
// centre through an axis-aligned tangent window, the per-micro-patch occlusion and FP16 rounding.
#include <algorithm>
#include <cmath>
#include <limits>

#include "penumbra/raster/projection.hpp"
#include "penumbra/shadows/depth_maps/ssm.hpp"

namespace penumbra::ssm {

namespace {

constexpr int kBand = 16;

DVec3 any_perpendicular(const DVec3& n) {
  const DVec3 h = std::abs(n.x) < 0.9 ? DVec3(1, 0, 0) : DVec3(0, 1, 0);
  return glm::normalize(glm::cross(h, n));
}

struct Tri {
  DVec3 s[3];
};

}  // namespace

LightRect light_rect(const Light& light, const DVec3& toward, double min_size) {
  LightRect r;
  r.c = DVec3(light.center);
  switch (light.shape) {
    case LightShape::rect: {
      const DVec3 eu(light.edge_u), ev(light.edge_v);
      r.a = glm::normalize(eu);
      // A parallelogram light is treated as the rectangle of its edge_u and the part of edge_v
      // perpendicular to it (the algorithm assumes a rectangle [Atty 2006 §3.1]).
      const DVec3 ev_perp = ev - glm::dot(ev, r.a) * r.a;
      r.b = glm::normalize(ev_perp);
      r.n = glm::normalize(glm::cross(eu, ev));
      r.lu = glm::length(eu);
      r.lv = glm::length(ev_perp);
      break;
    }
    case LightShape::disk:
    case LightShape::sphere: {
      r.n = light.shape == LightShape::disk ? glm::normalize(DVec3(light.normal))
                                            : glm::normalize(toward - r.c);
      r.a = any_perpendicular(r.n);
      r.b = glm::cross(r.n, r.a);
      r.lu = r.lv = std::sqrt(kPi) * light.radius;  // same area as the disk
      break;
    }
    case LightShape::point: {
      r.n = glm::normalize(toward - r.c);
      r.a = any_perpendicular(r.n);
      r.b = glm::cross(r.n, r.a);
      r.lu = r.lv = 0.0;
      break;
    }
  }
  if (!std::isfinite(r.n.x + r.n.y + r.n.z)) r.n = DVec3(0, -1, 0);
  r.lu = std::max(r.lu, min_size);
  r.lv = std::max(r.lv, min_size);
  return r;
}

Image<float> render_light_map(const Scene& scene, const std::vector<bool>& select,
                              const LightRect& light, const Window& window, MapFaces faces,
                              double near) {
  Image<float> map(window.w, window.h, kInfinity);
  if (window.empty()) return map;
  const bool keep_max = faces == MapFaces::back_furthest;
  if (keep_max) map = Image<float>(window.w, window.h, -kInfinity);
  const double mx = 0.5 * (window.tx0 + window.tx1), my = 0.5 * (window.ty0 + window.ty1);
  const double sx = 2.0 / (window.tx1 - window.tx0), sy = 2.0 / (window.ty1 - window.ty0);
  std::vector<Tri> tris;
  for (size_t m = 0; m < scene.meshes.size(); ++m) {
    if (m >= select.size() || !select[m]) continue;
    const Mesh& mesh = scene.meshes[m];
    for (size_t t = 0; t < mesh.triangle_count(); ++t) {
      const DVec3 p0(mesh.vertex(t, 0)), p1(mesh.vertex(t, 1)), p2(mesh.vertex(t, 2));
      const double side = glm::dot(glm::cross(p1 - p0, p2 - p0), light.c - p0);
      if (side == 0.0) continue;
      if (faces == MapFaces::front_nearest && side < 0.0) continue;
      if ((faces == MapFaces::back_nearest || faces == MapFaces::back_furthest) && side > 0.0)
        continue;
      // Clip space of the (possibly off-centre) window: x = (x_l − m_x·z)·s_x, w = z.
      DVec4 clip[3];
      const DVec3 ps[3] = {p0, p1, p2};
      for (int k = 0; k < 3; ++k) {
        const DVec3 l = light.local(ps[k]);
        clip[k] = DVec4((l.x - mx * l.z) * sx, (l.y - my * l.z) * sy, 1.0, l.z);
      }
      DVec4 out[kMaxClipVertices];
      const int n = clip_polygon(clip, 3, near, 1.01, out);
      if (n < 3) continue;
      DVec3 s[kMaxClipVertices];
      for (int k = 0; k < n; ++k) {
        const double inv_w = 1.0 / out[k].w;
        s[k] = DVec3((0.5 + 0.5 * out[k].x * inv_w) * window.w,
                     (0.5 - 0.5 * out[k].y * inv_w) * window.h, inv_w);
      }
      for (int k = 1; k + 1 < n; ++k) tris.push_back({{s[0], s[k], s[k + 1]}});
    }
  }
  const int bands = (window.h + kBand - 1) / kBand;
  std::vector<std::vector<uint32_t>> bins(bands);
  for (uint32_t i = 0; i < tris.size(); ++i) {
    const Tri& t = tris[i];
    const double ymin = std::min({t.s[0].y, t.s[1].y, t.s[2].y});
    const double ymax = std::max({t.s[0].y, t.s[1].y, t.s[2].y});
    const int b0 = std::clamp(static_cast<int>(std::floor((ymin - 0.5) / kBand)), 0, bands - 1);
    const int b1 = std::clamp(static_cast<int>(std::floor((ymax + 0.5) / kBand)), 0, bands - 1);
    for (int b = b0; b <= b1; ++b) bins[b].push_back(i);
  }
  parallel_bands(window.h, kBand, [&](int first, int last) {
    for (uint32_t i : bins[first / kBand]) {
      const Tri& t = tris[i];
      rasterize_triangle(t.s[0], t.s[1], t.s[2], window.w, first, last,
                         [&](int x, int y, double inv_w) {
                           if (!(inv_w > 0.0)) return;
                           const float d = static_cast<float>(1.0 / inv_w);
                           float& texel = map(x, y);
                           texel = keep_max ? std::max(texel, d) : std::min(texel, d);
                         });
    }
  });
  if (keep_max)
    for (float& d : map.pixels())
      if (d == -kInfinity) d = kInfinity;
  return map;
}

double patch_occlusion(double px, double py, double hx, double hy, double zo, double qx, double qy,
                       double zr, double lu, double lv) {
  if (!(zr > zo) || !(zo > 0.0)) return 0.0;
  // Back-projection from q through the patch onto the light plane z = 0: a patch point m maps to
  // q + (m − q)·s, s = z_R/(z_R − z_O) [Atty 2006 §3.4, Fig. 9]. A patch touching the receiver
  // makes s huge (§4.1.2); it stays finite (bounded by 1e12) and the overlaps are clamped.
  const double s = zr / std::max(zr - zo, zr * 1e-12);
  const double a = (qx + (px - hx - qx) * s) / lu + 0.5;
  const double b = (qx + (px + hx - qx) * s) / lu + 0.5;
  const double c = (qy + (py - hy - qy) * s) / lv + 0.5;
  const double d = (qy + (py + hy - qy) * s) / lv + 0.5;
  // MOV_SAT / SUB / MUL of §3.4: clamp to [0,1], interval lengths, product.
  const double wx = std::clamp(b, 0.0, 1.0) - std::clamp(a, 0.0, 1.0);
  const double wy = std::clamp(d, 0.0, 1.0) - std::clamp(c, 0.0, 1.0);
  return std::max(wx, 0.0) * std::max(wy, 0.0);
}

float round_to_half(float x, bool toward_zero) {
  if (!std::isfinite(x) || x == 0.0f) return x;
  const float ax = std::fabs(x);
  if (ax >= (toward_zero ? 65536.0f : 65520.0f))
    return toward_zero ? std::copysign(65504.0f, x)
                       : std::copysign(std::numeric_limits<float>::infinity(), x);
  int e = 0;
  std::frexp(ax, &e);  // ax = m·2^e, m ∈ [0.5, 1)
  // 11 significant bits (10 stored + implicit) down to the smallest subnormal 2^-24.
  const float ulp = std::ldexp(1.0f, std::max(e - 11, -24));
  const float q = ax / ulp;  // exact: a power-of-two scaling
  return std::copysign((toward_zero ? std::trunc(q) : std::nearbyint(q)) * ulp, x);
}

}  // namespace penumbra::ssm
