// Tests for the closed-form unshadowed irradiance (pipeline/irradiance.hpp): rectangles, disks,
// spheres and textured lights against textbook form factors and against dense quadratures of
// ∫ L cosθ cosθ' / r² dA (or, for the sphere, of ∫ cosθ dω over its cone), including lights that
// straddle the receiver's horizon, two-sided and one-sided lights.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <functional>

#include "penumbra/pipeline/irradiance.hpp"
#include "penumbra/render/receivers.hpp"

namespace penumbra {
namespace {

/// Midpoint rule on an n×n grid of the parallelogram corner + [0,1]² (edge_u, edge_v) of
/// ∫ radiance(uv) · max(0, n·w) · |cos_l| / r² dA (`one_sided`: cos_l must face p).
double quadrature(const DVec3& p, const DVec3& n, const DVec3& corner, const DVec3& edge_u,
                  const DVec3& edge_v, int grid, bool round = false,
                  const std::function<double(double, double)>& radiance = {}) {
  const DVec3 cross = glm::cross(edge_u, edge_v);
  const double area = glm::length(cross);
  const DVec3 light_n = cross / area;
  double sum = 0.0;
  for (int j = 0; j < grid; ++j)
    for (int i = 0; i < grid; ++i) {
      const double u = (i + 0.5) / grid, v = (j + 0.5) / grid;
      if (round && (u - 0.5) * (u - 0.5) + (v - 0.5) * (v - 0.5) > 0.25) continue;
      const DVec3 d = corner + u * edge_u + v * edge_v - p;
      const double r2 = glm::dot(d, d);
      const DVec3 w = d / std::sqrt(r2);
      const double cos_r = glm::dot(n, w), cos_l = std::abs(glm::dot(light_n, w));
      if (cos_r <= 0.0) continue;
      sum += (radiance ? radiance(u, v) : 1.0) * cos_r * cos_l / r2;
    }
  return sum * area / (static_cast<double>(grid) * grid);
}

/// Midpoint rule in polar coordinates (no staircase at the rim) of the same integral over the disk
/// centre + ρ(cos χ·u + sin χ·v), ρ ≤ r.
double disk_quadrature(const DVec3& p, const DVec3& n, const DVec3& center, const DVec3& u,
                       const DVec3& v, double r, int grid) {
  const DVec3 light_n = glm::cross(u, v);
  double sum = 0.0;
  for (int j = 0; j < grid; ++j)
    for (int i = 0; i < grid; ++i) {
      const double rho = (i + 0.5) / grid * r, chi = (j + 0.5) / grid * 2.0 * kPi;
      const DVec3 d = center + rho * (std::cos(chi) * u + std::sin(chi) * v) - p;
      const double r2 = glm::dot(d, d);
      const DVec3 w = d / std::sqrt(r2);
      const double cos_r = glm::dot(n, w);
      if (cos_r > 0.0) sum += rho * cos_r * std::abs(glm::dot(light_n, w)) / r2;
    }
  return sum * (r / grid) * (2.0 * kPi / grid);
}

double polygon_p(const DVec3& p, const DVec3& n, const DVec3& corner, const DVec3& edge_u,
                 const DVec3& edge_v) {
  const DVec3 quad[4] = {corner, corner + edge_u, corner + edge_u + edge_v, corner + edge_v};
  return polygon_projected_solid_angle(p, n, quad, 4);
}

TEST(Irradiance, RectangleMatchesTheCornerFormFactor) {
  // Point below a corner of an a×b rectangle parallel to the receiver at height h:
  // F = 1/(2π) [X/√(1+X²) atan(Y/√(1+X²)) + Y/√(1+Y²) atan(X/√(1+Y²))], X = a/h, Y = b/h.
  for (const auto& [a, b, h] : {std::tuple{1.0, 1.0, 1.0}, {0.3, 2.0, 0.7}, {5.0, 0.1, 2.0}}) {
    const double X = a / h, Y = b / h;
    const double F = (X / std::sqrt(1 + X * X) * std::atan(Y / std::sqrt(1 + X * X)) +
                      Y / std::sqrt(1 + Y * Y) * std::atan(X / std::sqrt(1 + Y * Y))) /
                     (2.0 * kPi);
    const double P =
        polygon_p(DVec3(0.0), DVec3(0, 0, 1), DVec3(0, 0, h), DVec3(a, 0, 0), DVec3(0, b, 0));
    EXPECT_NEAR(P, kPi * F, 2e-15) << a << " " << b << " " << h;
  }
}

TEST(Irradiance, RectangleMatchesDenseQuadratureAcrossTheHorizon) {
  // Tilted receivers, some seeing only part of the light above their horizon.
  const DVec3 corner(-0.5, 2.0, -0.25), edge_u(1.0, 0.1, 0.0), edge_v(0.0, -0.2, 0.5);
  const DVec3 normals[] = {{0, 1, 0}, {0.8, 0.6, 0}, {1, 0, 0}, {0.2, 0.1, -0.97}, {-1, 0.05, 0}};
  double worst = 0.0;
  for (DVec3 n : normals) {
    n = glm::normalize(n);
    for (const DVec3 p : {DVec3(0.0), DVec3(0.05, 1.5, 0.0), DVec3(-1.0, 0.5, 0.3)}) {
      const double exact = polygon_p(p, n, corner, edge_u, edge_v);
      const double dense = quadrature(p, n, corner, edge_u, edge_v, 1200);
      worst = std::max(worst, std::abs(exact - dense) / std::max(dense, 1e-3));
    }
  }
  // The midpoint rule's own error at 1200² (the kink of max(0, cosθ) at the horizon dominates):
  // measured 8.4e-7.
  EXPECT_LT(worst, 2e-6);
}

TEST(Irradiance, DiskOnAxisAndOffAxisParallel) {
  // On axis: P = π r² / (h² + r²). Off axis, parallel planes (d the offset):
  // F = ½ (1 − (Z − 2R²) / √(Z² − 4R²)), Z = 1 + H² + R², H = h/d, R = r/d.
  const DVec3 n(0, 0, 1), u(1, 0, 0), v(0, -1, 0);  // u × v = −z: faces the receiver
  EXPECT_NEAR(disk_projected_solid_angle(DVec3(0.0), n, DVec3(0, 0, 2), u, v, 0.5),
              kPi * 0.25 / (4.0 + 0.25), 2e-15);
  for (const auto& [h, d, r] : {std::tuple{1.0, 0.5, 0.3}, {2.0, 3.0, 1.0}, {0.5, 0.4, 0.6}}) {
    const double H = h / d, R = r / d, Z = 1 + H * H + R * R;
    const double F = 0.5 * (1.0 - (Z - 2 * R * R) / std::sqrt(Z * Z - 4 * R * R));
    // The classical result is for the element below a point at distance d from the centre.
    const double P = disk_projected_solid_angle(DVec3(d, 0, 0), n, DVec3(0, 0, h), u, v, r);
    EXPECT_NEAR(P, kPi * F, 2e-15) << h << " " << d << " " << r;
  }
}

TEST(Irradiance, DiskMatchesDenseQuadratureAcrossTheHorizon) {
  const DVec3 center(0.2, 1.5, -0.1);
  const DVec3 axis_n = glm::normalize(DVec3(0.3, -1.0, 0.2));
  DVec3 t = glm::normalize(glm::cross(axis_n, DVec3(1, 0, 0)));
  const DVec3 b = glm::cross(axis_n, t);
  const double r = 0.6;
  double worst = 0.0;
  int straddling = 0;
  for (DVec3 n : {DVec3(0, 1, 0), DVec3(1, 0.1, 0), DVec3(0.7, 0.7, 0.1), DVec3(-1, 0.3, 0.5),
                  DVec3(0, 0.05, 1)}) {
    n = glm::normalize(n);
    for (const DVec3 p : {DVec3(0.0), DVec3(0.3, 1.3, 0.2), DVec3(-1.0, 1.4, 0.0)}) {
      const double h0 = glm::dot(n, center - p),
                   amp = r * std::hypot(glm::dot(n, t), glm::dot(n, b));
      straddling += std::abs(h0) < amp;
      const double exact = disk_projected_solid_angle(p, n, center, t, b, r);
      const double dense = disk_quadrature(p, n, center, t, b, r, 1200);
      worst = std::max(worst, std::abs(exact - dense) / std::max(dense, 1e-3));
    }
  }
  EXPECT_GE(straddling, 4);  // the clipped-arc branch is exercised
  EXPECT_LT(worst, 1e-6);    // the polar midpoint rule at 1200²: measured 3.0e-7
}

TEST(Irradiance, SphereIsItsCapAboveAndAcrossTheHorizon) {
  Scene scene;
  Light light;
  light.shape = LightShape::sphere;
  light.center = Vec3(0.0f, 2.0f, 0.0f);
  light.radius = 0.5f;
  light.radiance = Vec3(1.0f);
  const LightIrradiance source(scene, light);
  // Wholly above the horizon: P = π sin²α cos β.
  for (const Vec3 n : {Vec3(0, 1, 0), glm::normalize(Vec3(0.3f, 1, 0))}) {
    const double sin2 = 0.25 / 4.0, cos_b = n.y;
    EXPECT_NEAR(source.at(Vec3(0.0f), n).x, kPi * sin2 * cos_b, 5e-8);  // float light frame: 1.7e-8
  }
  // Straddling: a quadrature over the cone's directions, ∫ max(0, n·ω) dω.
  const Vec3 n = glm::normalize(Vec3(1.0f, 0.1f, 0.0f));
  const double alpha = std::asin(0.25);
  const int grid = 1500;
  double dense = 0.0;
  for (int i = 0; i < grid; ++i)
    for (int j = 0; j < grid; ++j) {
      const double psi = (i + 0.5) / grid * alpha, chi = (j + 0.5) / grid * 2 * kPi;
      const DVec3 w(std::sin(psi) * std::cos(chi), std::cos(psi), std::sin(psi) * std::sin(chi));
      dense += std::max(0.0, glm::dot(DVec3(n), w)) * std::sin(psi);
    }
  dense *= (alpha / grid) * (2 * kPi / grid);
  EXPECT_NEAR(source.at(Vec3(0.0f), n).x, dense, 3e-7 * dense);  // measured 8.7e-8
}

TEST(Irradiance, OneSidedAndTwoSidedRectangles) {
  Scene scene;
  Light light;
  light.shape = LightShape::rect;
  light.center = Vec3(0.0f, 1.0f, 0.0f);
  light.edge_u = Vec3(0.5f, 0.0f, 0.0f);
  light.edge_v = Vec3(0.0f, 0.0f, 0.5f);  // emits toward −y
  light.radiance = Vec3(2.0f, 1.0f, 0.5f);
  const LightIrradiance below(scene, light);
  const Vec3 e = below.at(Vec3(0.0f), Vec3(0, 1, 0));
  const double P = polygon_p(DVec3(0.0), DVec3(0, 1, 0), DVec3(-0.25, 1, -0.25), DVec3(0.5, 0, 0),
                             DVec3(0, 0, 0.5));
  EXPECT_NEAR(e.x, 2.0 * P, 3e-8);  // float output: 7.9e-9
  EXPECT_NEAR(e.z, 0.5 * P, 1e-8);
  EXPECT_EQ(below.at(Vec3(0, 2, 0), Vec3(0, -1, 0)).x, 0.0f);  // behind a one-sided light
  light.two_sided = true;
  const LightIrradiance both(scene, light);
  EXPECT_NEAR(both.at(Vec3(0, 2, 0), Vec3(0, -1, 0)).x, 2.0 * P, 3e-8);
}

Scene scene_with_texture(int width, int height, const std::function<Vec3(int, int)>& texel) {
  Scene scene;
  Texture tex;
  tex.width = width;
  tex.height = height;
  tex.channels = 3;
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      const Vec3 c = texel(x, y);
      tex.texels.insert(tex.texels.end(), {c.x, c.y, c.z});
    }
  scene.textures.push_back(tex);
  return scene;
}

Light textured_light() {
  Light light;
  light.shape = LightShape::rect;
  light.center = Vec3(0.2f, 1.0f, 0.0f);
  light.edge_u = Vec3(1.0f, 0.0f, 0.0f);
  light.edge_v = Vec3(0.0f, 0.2f, 0.8f);
  light.emission_texture = 0;
  light.two_sided = true;
  return light;
}

TEST(Irradiance, TexturedLightIsTheSumOverTexels) {
  const Scene scene = scene_with_texture(
      3, 2, [](int x, int y) { return Vec3(0.1f + x + 3 * y, 1.0f, y == 0 ? 0.0f : 2.0f); });
  const Light light = textured_light();
  const LightIrradiance source(scene, light);
  EXPECT_EQ(source.blocks_u(), 3);
  const LightFrame f = light_frame(light, Vec3(0.0f));
  const Texture& tex = scene.textures[0];
  double worst = 0.0;
  for (DVec3 n : {DVec3(0, 1, 0), DVec3(1, 0.2, 0), DVec3(-0.6, 0.3, 0.7)}) {
    n = glm::normalize(n);
    const auto red = [&](double u, double v) {
      return static_cast<double>(tex.sample_rgb(Vec2(u, v)).x);
    };
    // The grid (1800) is a multiple of the texel counts: no midpoint straddles a texel edge.
    const double dense = quadrature(DVec3(0.0), n, DVec3(f.corner), DVec3(f.edge_u),
                                    DVec3(f.edge_v), 1800, false, red);
    const double exact = source.at(Vec3(0.0f), Vec3(n)).x;
    worst = std::max(worst, std::abs(exact - dense) / dense);
    const double grey =
        quadrature(DVec3(0.0), n, DVec3(f.corner), DVec3(f.edge_u), DVec3(f.edge_v), 1800);
    EXPECT_NEAR(source.at(Vec3(0.0f), Vec3(n)).y, grey, 3e-7 * grey);
  }
  EXPECT_LT(worst, 3e-7);  // measured 7.5e-8
}

TEST(Irradiance, LargeTexturesSumOverBlocksExactlyWhereBlocksAreUniform) {
  // 64×40 texels, uniform over 2×… blocks of the 32×32 block grid in u; v is not a multiple, so a
  // texture varying only in u keeps every block uniform.
  const Scene scene = scene_with_texture(
      64, 40, [](int x, int) { return Vec3(static_cast<float>((x / 2) % 5), 1.0f, 1.0f); });
  const Light light = textured_light();
  const LightIrradiance source(scene, light);
  EXPECT_EQ(source.blocks_u(), 32);
  EXPECT_EQ(source.blocks_v(), 32);
  const LightFrame f = light_frame(light, Vec3(0.0f));
  const Texture& tex = scene.textures[0];
  const DVec3 n = glm::normalize(DVec3(0.3, 1, 0.1));
  const double dense = quadrature(
      DVec3(0.0), n, DVec3(f.corner), DVec3(f.edge_u), DVec3(f.edge_v), 1920, false,
      [&](double u, double v) { return static_cast<double>(tex.sample_rgb(Vec2(u, v)).x); });
  EXPECT_NEAR(source.at(Vec3(0.0f), Vec3(n)).x, dense, 2e-7 * dense);
}

/// A 61×37 synthetic G-buffer under a one-sided rectangle: receivers on a bumpy floor, walls and
/// points above and behind the light, normals tilted so that the light crosses many receivers'
/// horizons; every 7th pixel inactive. fill() must give at() at every active pixel (its batches
/// of 8 differ only by glibc's vector atan2, a few double ulps: at most one float ulp after the
/// cast) and leave the others untouched.
TEST(Irradiance, FillEqualsAtEverywhere) {
  Scene scene;
  Light light;
  light.shape = LightShape::rect;
  light.center = Vec3(0.1f, 1.0f, -0.2f);
  light.edge_u = Vec3(0.6f, 0.05f, 0.0f);
  light.edge_v = Vec3(0.0f, 0.1f, 0.4f);
  light.radiance = Vec3(3.0f, 2.0f, 1.0f);
  GBuffer g;
  g.width = 61;
  g.height = 37;
  g.world_pos = Image<Vec3>(g.width, g.height);
  g.geo_normal = Image<Vec3>(g.width, g.height, Vec3(0, 1, 0));
  g.shading_normal = Image<Vec3>(g.width, g.height);
  g.ray_offset = Image<float>(g.width, g.height, 1e-4f);
  Image<uint8_t> classes(g.width, g.height, kActive);
  for (int y = 0; y < g.height; ++y)
    for (int x = 0; x < g.width; ++x) {
      const size_t i = static_cast<size_t>(y) * g.width + x;
      const float u = (x - 30.0f) / 20.0f, v = (y - 18.0f) / 12.0f;
      g.world_pos[i] = Vec3(u, y % 5 == 0 ? 1.5f : 0.1f * std::sin(3.0f * u), v);
      g.shading_normal[i] = glm::normalize(Vec3(std::sin(0.37f * x), 1.0f, std::cos(0.23f * y)));
      if (i % 7 == 3) classes[i] = kBackground;
    }
  const Vec3 sentinel(-7.0f);
  for (const bool two_sided : {false, true}) {
    light.two_sided = two_sided;
    const LightIrradiance source(scene, light);
    Image<Vec3> e(g.width, g.height, sentinel);
    source.fill(g, classes, e);
    int lit = 0, exact = 0;
    for (size_t i = 0; i < e.size(); ++i) {
      if (classes[i] != kActive) {
        EXPECT_EQ(e[i], sentinel) << i;
        continue;
      }
      const Vec3 want = source.at(g.shadow_origin(i), g.shading_normal[i]);
      for (int c = 0; c < 3; ++c)
        ASSERT_LE(std::abs(e[i][c] - want[c]), std::nextafter(want[c], 1e30f) - want[c])
            << "pixel " << i << " channel " << c;
      lit += want.x > 0.0f;
      exact += e[i] == want;
    }
    EXPECT_GT(lit, 1000);  // most receivers see some of the light
    EXPECT_GT(exact, lit * 9 / 10);
  }
}

}  // namespace
}  // namespace penumbra
