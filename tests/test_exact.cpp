// Tests of the exact reference (shadows/exact*.{hpp,cpp}): the per-point analytic visibility
// against closed forms, hand-computed cases and brute-force stratified sampling of segment–triangle
// tests written here (independent of every method and of Embree), then one whole frame.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <vector>

#include "penumbra/core/light_samples.hpp"
#include "penumbra/core/rng.hpp"
#include "penumbra/render/embree_scene.hpp"
#include "penumbra/render/gbuffer.hpp"
#include "penumbra/render/receivers.hpp"
#include "penumbra/scene/builtin_scenes.hpp"
#include "penumbra/scene/model_paths.hpp"
#include "penumbra/scene/shapes.hpp"
#include "penumbra/shadows/exact/exact.hpp"
#include "penumbra/shadows/exact/union_area.hpp"
#include "penumbra/shadows/registry.hpp"
#include "support/frame_helpers.hpp"

namespace penumbra {
namespace {

// ---------------------------------------------------------------------------------------------
// Scene building helpers

/// A scene with only a light: a 1×1 square at y = 2 centred on the y axis, facing down
/// (light uv: u = x + 0.5, v = z + 0.5), and one opaque material (index 0).
Scene light_only_scene() {
  Scene s;
  s.name = "exact-test";
  Material m;
  m.name = "opaque";
  s.materials.push_back(m);
  Light l;
  l.name = "light";
  l.shape = LightShape::rect;
  l.center = Vec3(0.0f, 2.0f, 0.0f);
  l.edge_u = Vec3(1.0f, 0.0f, 0.0f);
  l.edge_v = Vec3(0.0f, 0.0f, 1.0f);
  s.lights.push_back(l);
  return s;
}

int add_material(Scene& s, float transmittance, int alpha_texture = -1) {
  Material m;
  m.name = "m" + std::to_string(s.materials.size());
  m.transmittance = transmittance;
  m.alpha_texture = alpha_texture;
  s.materials.push_back(m);
  return static_cast<int>(s.materials.size() - 1);
}

void add_triangle(Scene& s, Vec3 a, Vec3 b, Vec3 c, int material = 0) {
  Mesh m;
  m.name = "tri";
  m.positions = {a, b, c};
  m.uvs = {{0, 0}, {1, 0}, {0, 1}};
  m.triangles = {{{0, 1, 2}}};
  m.material = material;
  s.meshes.push_back(std::move(m));
}

/// An axis-aligned horizontal rectangle [x0, x1] × [z0, z1] at height y (uv (0,0) at (x0, z0),
/// u along x, v along z).
void add_rect(Scene& s, float x0, float x1, float z0, float z1, float y, int material = 0) {
  Mesh m = make_quad(Vec3(0.5f * (x0 + x1), y, 0.5f * (z0 + z1)), Vec3(x1 - x0, 0, 0),
                     Vec3(0, 0, z1 - z0));
  m.material = material;
  s.meshes.push_back(std::move(m));
}

// ---------------------------------------------------------------------------------------------
// Brute force: stratified sampling of the light with exact segment–triangle tests over every
// triangle of the scene (no BVH), alpha looked up at each hit, transmittance multiplied.

bool segment_hits(const DVec3& o, const DVec3& d, const DVec3& a, const DVec3& b, const DVec3& c,
                  double& bu, double& bv) {
  return test::segment_crosses_triangle(o, d, a, b, c, &bu, &bv);
}

/// A triangle the brute force tests: vertices, the material, and where its uvs come from.
struct BruteTriangle {
  DVec3 a, b, c;
  const Mesh* mesh;
  size_t tri;
  const Material* material;
};

double transmitted(const Scene& s, const std::vector<BruteTriangle>& tris, const DVec3& o,
                   const DVec3& q) {
  const DVec3 d = q - o;
  double v = 1.0;
  for (const BruteTriangle& t : tris) {
    double bu = 0, bv = 0;
    if (!segment_hits(o, d, t.a, t.b, t.c, bu, bv)) continue;
    if (t.material->alpha_texture >= 0) {
      const Vec2 uv = t.mesh->uv_at(t.tri, static_cast<float>(bu), static_cast<float>(bv));
      if (s.textures[t.material->alpha_texture].sample_scalar(uv) < kAlphaCutoff) continue;
    }
    v *= t.material->transmittance;
    if (v == 0.0) return 0.0;
  }
  return v;
}

/// Visible fraction from k×k jittered stratified samples (default 448² ≈ 200k). Only triangles
/// whose bounding box meets the bounding box of the receiver and the light parallelogram can be
/// crossed, so only those are tested (a plain box overlap, nothing shared with the method).
double brute_force(const Scene& s, const Light& light, Vec3 p, int k = 448) {
  const LightFrame f = light_frame(light, p);
  const DVec3 o(p), corner(f.corner), eu(f.edge_u), ev(f.edge_v);
  DVec3 lo = glm::min(o, corner), hi = glm::max(o, corner);
  for (const DVec3& c : {corner + eu, corner + ev, corner + eu + ev}) {
    lo = glm::min(lo, c);
    hi = glm::max(hi, c);
  }
  std::vector<BruteTriangle> tris;
  for (const Mesh& mesh : s.meshes) {
    if (!mesh.casts_shadows) continue;
    for (size_t t = 0; t < mesh.triangle_count(); ++t) {
      const DVec3 a(mesh.vertex(t, 0)), b(mesh.vertex(t, 1)), c(mesh.vertex(t, 2));
      const DVec3 tlo = glm::min(a, glm::min(b, c)), thi = glm::max(a, glm::max(b, c));
      if (glm::any(glm::lessThan(thi, lo)) || glm::any(glm::greaterThan(tlo, hi))) continue;
      tris.push_back({a, b, c, &mesh, t, &s.material_of(mesh)});
    }
  }
  Pcg32 rng(12345, 7);
  double sum = 0.0;
  long count = 0;
  for (int j = 0; j < k; ++j) {
    for (int i = 0; i < k; ++i) {
      const double u = (i + rng.next_float()) / k, v = (j + rng.next_float()) / k;
      if (!f.emits(Vec2(static_cast<float>(u), static_cast<float>(v)))) continue;
      sum += transmitted(s, tris, o, corner + u * eu + v * ev);
      ++count;
    }
  }
  return count > 0 ? sum / static_cast<double>(count) : 1.0;
}

double exact_at(const Scene& s, Vec3 p, int disk_segments = 256) {
  const ExactScene es(s);
  return exact_visible_fraction(es, s.lights[0], p, disk_segments);
}

// ---------------------------------------------------------------------------------------------
// Closed forms

/// quad_scene_visible_fraction generalised to a receiver at height y (the frame test's shadow
/// origins sit ray_offset above the ground): distances to the light and occluder planes shrink.
double quad_closed_form(double x, double y, double z) {
  const QuadSceneGeometry g = kQuadScene;
  const double ratio = (g.light_height - y) / (g.occluder_height - y);
  const auto covered_1d = [&](double p) {
    const double half_o = 0.5 * g.occluder_side, half_l = 0.5 * g.light_side;
    const double lo = p + (-half_o - p) * ratio, hi = p + (half_o - p) * ratio;
    return std::clamp((std::min(hi, half_l) - std::max(lo, -half_l)) / g.light_side, 0.0, 1.0);
  };
  return 1.0 - covered_1d(x) * covered_1d(z);
}

// ---------------------------------------------------------------------------------------------

TEST(Exact, QuadSceneMatchesClosedFormOnTheGround) {
  const Scene s = make_builtin_scene("quad");
  const ExactScene es(s);
  const ExactLight light(s, s.lights[0]);
  int lit = 0, umbra = 0, penumbra = 0, probes = 0;
  double worst = 0.0;
  for (int j = 0; j <= 24; ++j) {
    for (int i = 0; i <= 24; ++i) {
      // Irrational-ish offsets so probes do not sit on special lines only.
      const float x = -1.6f + 3.2f * static_cast<float>(i) / 24.0f + 0.0123f;
      const float z = -1.6f + 3.2f * static_cast<float>(j) / 24.0f - 0.0071f;
      const double closed = quad_scene_visible_fraction(x, z);
      const ExactPointResult r = exact_visibility(es, light, Vec3(x, 0.0f, z));
      EXPECT_NEAR(r.visible, closed, 1e-5) << "at (" << x << ", 0, " << z << ")";
      EXPECT_FALSE(r.degenerate);
      worst = std::max(worst, std::abs(r.visible - closed));
      ++probes;
      if (closed == 1.0)
        ++lit;
      else if (closed == 0.0)
        ++umbra;
      else
        ++penumbra;
    }
  }
  EXPECT_GE(probes, 200);
  EXPECT_GT(lit, 20);
  EXPECT_GT(umbra, 20);
  EXPECT_GT(penumbra, 100);
  std::printf("quad: %d probes (%d lit, %d umbra, %d penumbra), max |exact - closed form| = %.3g\n",
              probes, lit, umbra, penumbra, worst);
}

TEST(Exact, QuadClosedFormGeneralisationAgreesWithTheScenes) {
  for (double y : {0.0, 0.0014, 0.3})
    for (double x = -1.5; x <= 1.5; x += 0.37)
      for (double z = -1.5; z <= 1.5; z += 0.41)
        EXPECT_NEAR(quad_closed_form(x, y, z), quad_scene_visible_fraction(x, y, z), 1e-14);
}

TEST(Exact, RaisedReceiverMatchesGeneralisedClosedForm) {
  const Scene s = make_builtin_scene("quad");
  for (float y : {0.01f, 0.3f, 0.7f})
    for (float x : {-0.9f, -0.31f, 0.0f, 0.44f})
      for (float z : {-0.7f, 0.13f, 0.52f})
        EXPECT_NEAR(exact_at(s, Vec3(x, y, z)), quad_closed_form(x, y, z), 1e-6);
}

TEST(Exact, SingleTriangleHandComputed) {
  // From the origin, the occluder at y = 1 projects ×2 onto the light plane y = 2: the legs of
  // 0.375 become 0.75, the triangle (0.5,0.5), (1.25,0.5), (0.5,1.25) in light uv. Inside the
  // light it covers [0.5,1]² minus the corner beyond u + v = 1.75: 0.25 − 0.25²/2 = 0.21875.
  Scene s = light_only_scene();
  add_triangle(s, Vec3(0, 1, 0), Vec3(0.375f, 1, 0), Vec3(0, 1, 0.375f));
  EXPECT_NEAR(exact_at(s, Vec3(0.0f)), 1.0 - 0.21875, 1e-8);
  // Reversed winding: same answer.
  Scene r = light_only_scene();
  add_triangle(r, Vec3(0, 1, 0), Vec3(0, 1, 0.375f), Vec3(0.375f, 1, 0));
  EXPECT_NEAR(exact_at(r, Vec3(0.0f)), 1.0 - 0.21875, 1e-8);
}

TEST(Exact, TriangleStraddlingTheLightPlaneMatchesBruteForce) {
  // Part of the triangle lies above the light plane (y > 2), where it blocks nothing.
  Scene s = light_only_scene();
  add_triangle(s, Vec3(-0.3f, 1.0f, -0.2f), Vec3(0.4f, 2.6f, 0.1f), Vec3(0.1f, 2.5f, 0.5f));
  for (const Vec3 p : {Vec3(0.0f), Vec3(0.3f, 0.0f, -0.2f), Vec3(-0.5f, 0.2f, 0.4f)}) {
    const double e = exact_at(s, p), b = brute_force(s, s.lights[0], p);
    EXPECT_NEAR(e, b, 3e-3) << "at " << p.x << "," << p.y << "," << p.z;
    std::printf("straddling light plane: exact %.6f brute force %.6f\n", e, b);
  }
  EXPECT_LT(exact_at(s, Vec3(0.0f)), 0.95);
  EXPECT_GT(exact_at(s, Vec3(0.0f)), 0.05);
}

TEST(Exact, TriangleStraddlingTheReceiverPlaneMatchesBruteForce) {
  // Part of the triangle lies below the receiver's plane parallel to the light (y < 0 here),
  // including vertices behind the receiver, where the perspective divide would flip sign.
  Scene s = light_only_scene();
  add_triangle(s, Vec3(0.3f, -0.5f, -0.1f), Vec3(0.1f, 0.8f, 0.1f), Vec3(0.35f, 0.6f, 0.45f));
  add_triangle(s, Vec3(-0.2f, -0.4f, 0.3f), Vec3(0.15f, 0.5f, -0.3f), Vec3(-0.3f, 0.9f, -0.2f));
  for (const Vec3 p : {Vec3(0.0f), Vec3(0.1f, 0.0f, 0.05f), Vec3(-0.1f, 0.05f, 0.15f)}) {
    const double e = exact_at(s, p), b = brute_force(s, s.lights[0], p);
    EXPECT_NEAR(e, b, 3e-3) << "at " << p.x << "," << p.y << "," << p.z;
    EXPECT_GT(e, 0.02);
    EXPECT_LT(e, 0.999);
    std::printf("straddling receiver plane: exact %.6f brute force %.6f\n", e, b);
  }
}

TEST(Exact, OverlappingOccludersCountTheirUnionOnce) {
  // From the origin, A (y = 1, ×2) covers light uv [0.2, 0.6]², B (y = 0.5, ×4) covers
  // [0.4, 0.8]²: union 0.16 + 0.16 − 0.04 = 0.28, not the sum 0.32.
  Scene s = light_only_scene();
  add_rect(s, -0.15f, 0.05f, -0.15f, 0.05f, 1.0f);
  add_rect(s, -0.025f, 0.075f, -0.025f, 0.075f, 0.5f);
  EXPECT_NEAR(exact_at(s, Vec3(0.0f)), 0.72, 1e-6);
  EXPECT_NEAR(exact_at(s, Vec3(0.0f)), brute_force(s, s.lights[0], Vec3(0.0f), 256), 3e-3);
}

TEST(Exact, DiskLightMatchesBruteForce) {
  Scene s = light_only_scene();
  s.lights[0].shape = LightShape::disk;
  s.lights[0].radius = 0.5f;
  s.lights[0].normal = Vec3(0.0f, -1.0f, 0.0f);
  add_triangle(s, Vec3(-0.3f, 1.0f, -0.4f), Vec3(0.35f, 1.1f, 0.0f), Vec3(-0.1f, 0.9f, 0.45f));
  add_rect(s, 0.05f, 0.4f, -0.5f, -0.1f, 1.3f);
  for (const Vec3 p : {Vec3(0.0f), Vec3(0.25f, 0.0f, 0.1f), Vec3(-0.4f, 0.0f, -0.3f)}) {
    const double e = exact_at(s, p), b = brute_force(s, s.lights[0], p);
    EXPECT_NEAR(e, b, 3e-3);
    std::printf("disk: exact %.6f brute force %.6f\n", e, b);
  }
  // The equal-area polygon's error bound, 0.128·(π/N)²: N = 64 vs N = 4096 differ by less.
  const Vec3 p(0.25f, 0.0f, 0.1f);
  const double h64 = kPi / 64;
  EXPECT_LE(std::abs(exact_at(s, p, 64) - exact_at(s, p, 4096)), 0.1284 * h64 * h64 + 1e-7);
}

TEST(Exact, SphereLightMatchesBruteForceOverItsSilhouetteDisk) {
  Scene s = light_only_scene();
  s.lights[0].shape = LightShape::sphere;
  s.lights[0].radius = 0.4f;
  add_triangle(s, Vec3(-0.3f, 1.0f, -0.4f), Vec3(0.35f, 1.1f, 0.0f), Vec3(-0.1f, 0.9f, 0.45f));
  for (const Vec3 p : {Vec3(0.0f), Vec3(0.6f, 0.0f, 0.2f)}) {
    const double e = exact_at(s, p), b = brute_force(s, s.lights[0], p);
    EXPECT_NEAR(e, b, 3e-3);
    std::printf("sphere: exact %.6f brute force %.6f\n", e, b);
  }
}

/// A 2×2 checkerboard alpha texture: texels (0,0) and (1,1) opaque.
int add_checkerboard(Scene& s) {
  Texture t;
  t.name = "checker";
  t.width = t.height = 2;
  t.channels = 1;
  t.texels = {1.0f, 0.0f, 0.0f, 1.0f};
  s.textures.push_back(t);
  return static_cast<int>(s.textures.size() - 1);
}

TEST(Exact, AlphaCheckerboardEqualsItsTwoOpaqueSquares) {
  // Quad [-0.2, 0.2]² at y = 1 with uv (0,0) at (-0.2, -0.2): opaque where u, v < 0.5 or
  // u, v ≥ 0.5, i.e. the squares [-0.2, 0]² and [0, 0.2]².
  Scene cut = light_only_scene();
  add_rect(cut, -0.2f, 0.2f, -0.2f, 0.2f, 1.0f, add_material(cut, 0.0f, add_checkerboard(cut)));
  Scene plain = light_only_scene();
  add_rect(plain, -0.2f, 0.0f, -0.2f, 0.0f, 1.0f);
  add_rect(plain, 0.0f, 0.2f, 0.0f, 0.2f, 1.0f);
  const ExactScene es_cut(cut), es_plain(plain);
  EXPECT_GT(es_cut.pieces().size(), 0u);
  for (const Vec3 p :
       {Vec3(0.0f), Vec3(0.13f, 0.0f, -0.07f), Vec3(-0.35f, 0.2f, 0.3f), Vec3(0.6f, 0.0f, 0.5f)}) {
    const double a = exact_visible_fraction(es_cut, cut.lights[0], p);
    const double b = exact_visible_fraction(es_plain, plain.lights[0], p);
    EXPECT_NEAR(a, b, 1e-6);
    EXPECT_LT(a, 1.0);
  }
  // Tiled twice (uv over [0, 2]²): the same as eight plain squares.
  Scene tiled = light_only_scene();
  Mesh q = make_quad(Vec3(0.0f, 1.0f, 0.0f), Vec3(0.4f, 0, 0), Vec3(0, 0, 0.4f));
  for (Vec2& uv : q.uvs) uv *= 2.0f;
  q.material = add_material(tiled, 0.0f, add_checkerboard(tiled));
  tiled.meshes.push_back(q);
  Scene squares = light_only_scene();
  for (int j = 0; j < 4; ++j) {
    for (int i = 0; i < 4; ++i) {
      if ((i + j) % 2 == 0)
        add_rect(squares, -0.2f + 0.1f * i, -0.1f + 0.1f * i, -0.2f + 0.1f * j, -0.1f + 0.1f * j,
                 1.0f);
    }
  }
  for (const Vec3 p : {Vec3(0.0f), Vec3(0.21f, 0.0f, 0.05f)})
    EXPECT_NEAR(exact_at(tiled, p), exact_at(squares, p), 1e-6);
}

TEST(Exact, FenceAlphaMatchesBruteForce) {
  const Scene s = make_builtin_scene("fence");
  const ExactScene es(s);
  std::printf("fence: %zu occluder triangles, %zu alpha pieces\n", es.occluders().size(),
              es.pieces().size());
  for (const Vec3 p :
       {Vec3(0.05f, 0.0f, 0.1f), Vec3(0.5f, 0.0f, -0.3f), Vec3(-0.2f, 0.3f, 0.45f)}) {
    const double e = exact_visible_fraction(es, s.lights[0], p), b = brute_force(s, s.lights[0], p);
    EXPECT_NEAR(e, b, 3e-3);
    std::printf("fence: exact %.6f brute force %.6f\n", e, b);
  }
}

TEST(Exact, AlphaMaskUnderShearedTiledUvsMatchesBruteForce) {
  // A random 8×5 mask on a triangle whose uvs are rotated, sheared and span several periods
  // (including negative ones): the general decomposition into texel-run pieces.
  Scene s = light_only_scene();
  Texture t;
  t.name = "random-mask";
  t.width = 8;
  t.height = 5;
  Pcg32 rng(21, 22);
  for (int k = 0; k < t.width * t.height; ++k) t.texels.push_back(rng.next_float());
  s.textures.push_back(t);
  Mesh m;
  m.name = "sheared";
  m.positions = {Vec3(-0.3f, 1.0f, -0.25f), Vec3(0.35f, 1.1f, -0.1f), Vec3(-0.05f, 0.9f, 0.4f)};
  m.uvs = {Vec2(-0.7f, 0.2f), Vec2(1.3f, -0.9f), Vec2(0.4f, 1.6f)};
  m.triangles = {{{0, 1, 2}}};
  m.material = add_material(s, 0.0f, 0);
  s.meshes.push_back(m);
  const ExactScene es(s);
  EXPECT_GT(es.pieces().size(), 10u);
  for (const Vec3 p : {Vec3(0.0f), Vec3(0.15f, 0.0f, -0.1f)}) {
    const double e = exact_visible_fraction(es, s.lights[0], p), b = brute_force(s, s.lights[0], p);
    EXPECT_NEAR(e, b, 3e-3);
    EXPECT_LT(e, 0.99);
    std::printf("sheared alpha: exact %.6f brute force %.6f\n", e, b);
  }
}

TEST(Exact, SemiOpaqueLayersMultiply) {
  Scene one = light_only_scene();
  const int glass = add_material(one, 0.5f);
  add_rect(one, -1.0f, 1.0f, -1.0f, 1.0f, 1.0f, glass);  // covers the whole light from the origin
  EXPECT_NEAR(exact_at(one, Vec3(0.0f)), 0.5, 1e-9);
  Scene two = one;
  add_rect(two, -1.0f, 1.0f, -1.0f, 1.0f, 1.5f, glass);
  EXPECT_NEAR(exact_at(two, Vec3(0.0f)), 0.25, 1e-9);
  // Partial layers with different transmittances and an opaque occluder: brute force.
  Scene mixed = light_only_scene();
  add_rect(mixed, -0.2f, 0.15f, -0.3f, 0.1f, 1.0f, add_material(mixed, 0.5f));
  add_rect(mixed, -0.05f, 0.3f, -0.1f, 0.25f, 0.8f, add_material(mixed, 0.3f));
  add_triangle(mixed, Vec3(-0.1f, 1.2f, -0.1f), Vec3(0.2f, 1.2f, 0.0f), Vec3(0.0f, 1.2f, 0.3f));
  for (const Vec3 p : {Vec3(0.0f), Vec3(0.1f, 0.0f, -0.15f)}) {
    const double e = exact_at(mixed, p), b = brute_force(mixed, mixed.lights[0], p);
    EXPECT_NEAR(e, b, 3e-3);
    std::printf("semi-opaque mix: exact %.6f brute force %.6f\n", e, b);
  }
}

TEST(Exact, TexturedLightWeightsTheTexels) {
  // Emission 2×1: left texel red, right texel blue. The occluder at y = 1, x ∈ [-0.25, 0],
  // hides exactly the left half of the light (u < 0.5) from the origin.
  Scene s = light_only_scene();
  Texture t;
  t.name = "red-blue";
  t.width = 2;
  t.height = 1;
  t.channels = 3;
  t.texels = {1, 0, 0, 0, 0, 1};
  s.textures.push_back(t);
  s.lights[0].emission_texture = 0;
  add_rect(s, -0.25f, 0.0f, -0.4f, 0.4f, 1.0f);
  const ExactScene es(s);
  const ExactLight light(s, s.lights[0]);
  ASSERT_TRUE(light.textured());
  const ExactPointResult r = exact_visibility(es, light, Vec3(0.0f));
  EXPECT_NEAR(r.visible_rgb.x, 0.0, 1e-8);   // red: all hidden
  EXPECT_NEAR(r.visible_rgb.y, 1.0, 1e-12);  // green: not emitted; reads 1 (light_weights.hpp)
  EXPECT_NEAR(r.visible_rgb.z, 1.0, 1e-8);   // blue: all visible
  // Luminance-weighted: Y(blue) / (Y(red) + Y(blue)).
  EXPECT_NEAR(r.visible, 0.0722 / (0.2126 + 0.0722), 1e-8);
  // Moving the receiver shows part of the red texel: lit_rgb.x > 0, blue unchanged.
  const ExactPointResult moved = exact_visibility(es, light, Vec3(0.1f, 0.0f, 0.0f));
  // From x = 0.1 the occluder's right edge x = 0 projects to light x = -0.1 (u = 0.4): a fifth
  // of the red texel shows, blue stays fully visible.
  EXPECT_NEAR(moved.visible_rgb.x, 0.2, 1e-6);
  EXPECT_NEAR(moved.visible_rgb.z, 1.0, 1e-9);
}

TEST(Exact, PointLightIsHard) {
  Scene s = light_only_scene();
  s.lights[0].shape = LightShape::point;
  add_triangle(s, Vec3(-0.1f, 1.0f, -0.1f), Vec3(0.2f, 1.0f, -0.1f), Vec3(-0.1f, 1.0f, 0.2f));
  EXPECT_EQ(exact_at(s, Vec3(0.0f)), 0.0);
  EXPECT_EQ(exact_at(s, Vec3(0.5f, 0.0f, 0.5f)), 1.0);
  // Semi-opaque: its transmittance; alpha hole: unblocked.
  Scene semi = light_only_scene();
  semi.lights[0].shape = LightShape::point;
  add_rect(semi, -0.5f, 0.5f, -0.5f, 0.5f, 1.0f, add_material(semi, 0.25f));
  // (Not through the quad's diagonal: a segment through an edge shared by two triangles of a
  // semi-opaque mesh is numerically ambiguous — it crosses both.)
  EXPECT_DOUBLE_EQ(exact_at(semi, Vec3(0.05f, 0.0f, -0.1f)), 0.25);
  Scene holes = light_only_scene();
  holes.lights[0].shape = LightShape::point;
  add_rect(holes, -0.2f, 0.2f, -0.2f, 0.2f, 1.0f,
           add_material(holes, 0.0f, add_checkerboard(holes)));
  EXPECT_EQ(exact_at(holes, Vec3(-0.1f, 0.0f, -0.1f)), 0.0);  // opaque texel (0,0)
  EXPECT_EQ(exact_at(holes, Vec3(0.1f, 0.0f, -0.1f)), 1.0);   // hole texel (1,0)
}

TEST(Exact, ReceiverInTheLightPlaneFallsBackToLit) {
  Scene s = light_only_scene();
  add_rect(s, -0.3f, 0.3f, -0.3f, 0.3f, 1.0f);
  const ExactScene es(s);
  const ExactLight light(s, s.lights[0]);
  const ExactPointResult r = exact_visibility(es, light, Vec3(3.0f, 2.0f, 0.0f));
  EXPECT_TRUE(r.degenerate);
  EXPECT_EQ(r.visible, 1.0);
  const ExactPointResult nan = exact_visibility(es, light, Vec3(std::nanf(""), 0.0f, 0.0f));
  EXPECT_TRUE(nan.degenerate);
  EXPECT_EQ(nan.visible, 1.0);
}

TEST(Exact, NeverNaNAndWithinRangeNearGeometry) {
  // Receivers on, just above and inside occluders: values stay finite in [0, 1].
  const Scene s = make_builtin_scene("default");
  const ExactScene es(s);
  const ExactLight light(s, s.lights[0]);
  Pcg32 rng(3, 4);
  for (int k = 0; k < 400; ++k) {
    const Vec3 p(-1.0f + 2.0f * rng.next_float(), 1.3f * rng.next_float(),
                 -1.0f + 2.0f * rng.next_float());
    const ExactPointResult r = exact_visibility(es, light, p);
    EXPECT_TRUE(std::isfinite(r.visible));
    EXPECT_GE(r.visible, 0.0);
    EXPECT_LE(r.visible, 1.0);
  }
}

TEST(Exact, BvhFindsEveryTriangleABruteForceBoxTestFinds) {
  // The BVH traversal must visit every triangle whose own box passes the same plane test.
  const Scene s = make_builtin_scene("spheres");
  for (int leaf : {1, 4, 16}) {
    const ExactScene es(s, leaf);
    Pcg32 rng(5, 6);
    for (int k = 0; k < 50; ++k) {
      const Vec3 p(-1.5f + 3.0f * rng.next_float(), 0.6f * rng.next_float(),
                   -1.5f + 3.0f * rng.next_float());
      const LightFrame f = light_frame(s.lights[0], p);
      LightProjection proj;
      ASSERT_TRUE(
          make_light_projection(DVec3(p), DVec3(f.corner), DVec3(f.edge_u), DVec3(f.edge_v), proj));
      std::vector<char> visited(es.occluders().size(), 0);
      es.bvh().traverse(
          [&](const ExactBvh::Node& n) { return box_meets_pyramid(proj, n.lo, n.hi); },
          [&](uint32_t prim) {
            visited[prim] = 1;
            return true;
          });
      for (size_t t = 0; t < es.occluders().size(); ++t) {
        const ExactOccluder& o = es.occluders()[t];
        Bounds3 b;
        for (const DVec3& v : o.v) b.extend(Vec3(v));
        if (box_meets_pyramid(proj, b.lo, b.hi)) {
          EXPECT_TRUE(visited[t]) << "triangle " << t;
        }
      }
    }
    EXPECT_LE(es.bvh().depth(), ExactBvh::kMaxDepth);
  }
}

TEST(Exact, LeafSizeDoesNotChangeTheAnswer) {
  const Scene s = make_builtin_scene("spheres");
  const ExactScene a(s, 1), b(s, 16);
  Pcg32 rng(8, 9);
  for (int k = 0; k < 60; ++k) {
    const Vec3 p(-1.0f + 2.0f * rng.next_float(), 0.0f, -1.0f + 2.0f * rng.next_float());
    EXPECT_NEAR(exact_visible_fraction(a, s.lights[0], p),
                exact_visible_fraction(b, s.lights[0], p), 1e-9);
  }
}

TEST(Exact, SpheresSceneAgreesWithBruteForceSampling) {
  const Scene s = make_builtin_scene("spheres");
  const ExactScene es(s);
  for (const Vec3 p : {Vec3(0.35f, 0.0f, 0.25f), Vec3(0.9f, 0.0f, 0.6f), Vec3(-0.2f, 0.0f, 0.1f)}) {
    const double e = exact_visible_fraction(es, s.lights[0], p),
                 b = brute_force(s, s.lights[0], p, 128);
    EXPECT_NEAR(e, b, 3e-3);
    std::printf("spheres: exact %.6f brute force (128²) %.6f\n", e, b);
  }
}

/// Every occluder triangle of `es` projected from p onto the light (project_polygon), none skipped.
ClipperLib::Paths projected_triangles(const ExactScene& es, const Light& light, const Vec3& p) {
  const LightFrame f = light_frame(light, p);
  LightProjection proj;
  ClipperLib::Paths polys;
  if (!make_light_projection(DVec3(p), DVec3(f.corner), DVec3(f.edge_u), DVec3(f.edge_v), proj)) {
    ADD_FAILURE() << "no projection";
    return polys;
  }
  ClipperLib::Path poly;
  for (const ExactOccluder& o : es.occluders())
    if (project_polygon(proj, o.v, 3, poly)) polys.push_back(poly);
  return polys;
}

TEST(Exact, EdgeCancellationKeepsTheUnion) {
  // The projected triangles of the spheres scene from ground points: the union of the cancelled
  // loops must have the area of Clipper's direct union of all triangles.
  const Scene s = make_builtin_scene("spheres");
  const ExactScene es(s);
  Pcg32 rng(10, 11);
  int tested = 0;
  for (int k = 0; k < 40; ++k) {
    const Vec3 p(-0.9f + 1.8f * rng.next_float(), 0.0f, -0.9f + 1.8f * rng.next_float());
    const ClipperLib::Paths polys = projected_triangles(es, s.lights[0], p);
    if (polys.size() < 10) continue;
    ++tested;
    const ClipperLib::Paths loops = cancel_shared_edges(polys);
    EXPECT_LT(loops.size() * 10, polys.size());
    ClipperLib::Clipper direct, cancelled;
    direct.AddPaths(polys, ClipperLib::ptSubject, true);
    cancelled.AddPaths(loops, ClipperLib::ptSubject, true);
    ClipperLib::Paths a, b;
    direct.Execute(ClipperLib::ctUnion, a, ClipperLib::pftNonZero, ClipperLib::pftNonZero);
    cancelled.Execute(ClipperLib::ctUnion, b, ClipperLib::pftNonZero, ClipperLib::pftNonZero);
    EXPECT_NEAR(paths_area(a) / kUvArea, paths_area(b) / kUvArea, 1e-9);
    EXPECT_NEAR(paths_area(union_polygons(polys, 8)) / kUvArea, paths_area(a) / kUvArea, 1e-9);
  }
  EXPECT_GT(tested, 10);
}

/// V at p by Clipper's direct union of every triangle `scene` projects (no edge skipped, no
/// triangle culled, one polygon operation): the oracle of exact's sweeps.
double direct_union_visibility(const ExactScene& scene, const Light& l, const ExactLight& light,
                               const Vec3& p) {
  ClipperLib::Clipper c;
  c.AddPath(light.outline().path, ClipperLib::ptSubject, true);
  c.AddPaths(projected_triangles(scene, l, p), ClipperLib::ptClip, true);
  ClipperLib::Paths left;
  c.Execute(ClipperLib::ctDifference, left, ClipperLib::pftNonZero, ClipperLib::pftNonZero);
  return paths_area(left) / light.outline().area;
}

TEST(Exact, AdjacencySkippedEdgesKeepTheUnion) {
  // exact_visibility never projects the shared edges of kept mesh triangles (nor the triangles
  // inside the pyramid whose three neighbours are kept): its V must equal the area left by
  // Clipper's direct union of every projected triangle, no edge skipped, no triangle culled.
  for (const char* name : {"spheres", "default"}) {
    Scene s = make_builtin_scene(name);
    for (Material& m : s.materials) {  // opaque and uncut: the direct union below projects whole
      m.transmittance = 0.0f;          // triangles
      m.alpha_texture = -1;
    }
    const ExactScene es(s, 4, true), full(s, 4, false);
    const ExactLight light(s, s.lights[0]);
    Pcg32 rng(12, 13);
    int shadowed = 0;
    double max_diff = 0.0;
    for (int k = 0; k < 30; ++k) {
      const Vec3 p(-1.2f + 2.4f * rng.next_float(), 0.0f, -1.2f + 2.4f * rng.next_float());
      const double direct = direct_union_visibility(full, s.lights[0], light, p);
      if (direct < 1.0 - 1e-9) ++shadowed;
      for (const ExactScene* scene : {&es, &full}) {
        const double v = exact_visibility(*scene, light, p).visible;
        max_diff = std::max(max_diff, std::abs(v - direct));
        EXPECT_NEAR(v, direct, 1e-9) << name << " receiver " << k;
      }
    }
    std::printf("%s: %d shadowed receivers, max |V - direct union| %.3g\n", name, shadowed,
                max_diff);
    EXPECT_GT(shadowed, 5);
  }
}

/// `count` equal triangles stacked `spacing` apart from y = 0.5 above the origin, in one mesh of
/// disconnected triangles, under a 0.6 square light at y = 2.5 (the stacked-occluder case: from a
/// ground receiver every copy projects onto nearly the same polygon, their edges crossing).
Scene stacked_triangles_scene(int count, float spacing = 1e-4f) {
  Scene s = light_only_scene();
  s.lights[0].center = Vec3(0.0f, 2.5f, 0.0f);
  s.lights[0].edge_u = Vec3(0.6f, 0.0f, 0.0f);
  s.lights[0].edge_v = Vec3(0.0f, 0.0f, 0.6f);
  Mesh m;
  m.name = "stack";
  for (int k = 0; k < count; ++k) {
    const float y = 0.5f + spacing * static_cast<float>(k);
    const uint32_t first = static_cast<uint32_t>(m.positions.size());
    m.positions.insert(m.positions.end(), {Vec3(0, y, 0), Vec3(1, y, 0), Vec3(0, y, 1)});
    m.triangles.push_back({{first, first + 1, first + 2}});
  }
  s.meshes.push_back(std::move(m));
  return s;
}

TEST(Exact, StackedTrianglesEqualTheirDirectUnionAndSampling) {
  // 1 000 stacked copies: the sweep divides their ~3 000 edges; V must equal Clipper's direct
  // union of every projected triangle, and the sampled visibility of independent segment tests.
  const Scene s = stacked_triangles_scene(1000);
  const ExactScene es(s);
  const ExactLight light(s, s.lights[0]);
  int penumbra = 0;
  for (const float x : {-0.06f, -0.02f, 0.03f, 0.6f, 0.75f, 0.9f}) {
    const Vec3 p(x, 0.0f, 0.3f);
    const size_t polygons = projected_triangles(es, s.lights[0], p).size();
    const double direct = direct_union_visibility(es, s.lights[0], light, p);
    const ExactPointResult r = exact_visibility(es, light, p);
    EXPECT_NEAR(r.visible, direct, 1e-9) << "x " << x;
    const double sampled = brute_force(s, s.lights[0], p, 128);
    EXPECT_NEAR(r.visible, sampled, 3e-3) << "x " << x;
    penumbra += r.visible > 0.02 && r.visible < 0.98 && polygons > 500 ? 1 : 0;
    std::printf("stack x %.2f: %zu polygons, exact %.6f direct %.6f sampled %.6f\n", x, polygons,
                r.visible, direct, sampled);
  }
  EXPECT_GE(penumbra, 4);
}

TEST(Exact, StackedTrianglesSweepWorkGrowsAsNLogN) {
  // The sweep's work on a row of ground receivers across the stack's shadow, for 1 000 and
  // 4 000 copies in the same height (0.1): a single sweep over every edge grew about 16× (each
  // copy's edges in each beam); divided, as N·log2(edges / kLeafEdges), the merge tree's levels.
  uint64_t work[2] = {0, 0};
  const int counts[2] = {1000, 4000};
  for (int i = 0; i < 2; ++i) {
    const Scene s = stacked_triangles_scene(counts[i], 0.1f / static_cast<float>(counts[i]));
    const ExactScene es(s);
    const ExactLight light(s, s.lights[0]);
    for (int k = 0; k <= 36; ++k)
      work[i] += exact_visibility(es, light, Vec3(-0.3f + 0.05f * k, 0.0f, 0.3f)).sweep_edge_beams;
  }
  const double ratio = static_cast<double>(work[1]) / static_cast<double>(work[0]);
  std::printf("sweep work 1000 -> 4000 copies: %llu -> %llu (%.2fx)\n",
              static_cast<unsigned long long>(work[0]), static_cast<unsigned long long>(work[1]),
              ratio);
  EXPECT_GT(work[0], 10000u);
  const double leaves = static_cast<double>(kLeafEdges);
  EXPECT_LE(ratio, 4.0 * std::log2(12000.0 / leaves) / std::log2(3000.0 / leaves));  // 5.22
}

TEST(Exact, ManyMeshesInThePyramidEqualTheirDirectUnion) {
  // 60 small closed spheres and 60 boxes between the ground and the light: from a ground
  // receiver under them, hundreds of silhouette edges reach the sweep, which divides them by
  // groups of triangles joined by cancelled edges (each sphere's front or back, each box's
  // faces). V must equal Clipper's direct union of every projected triangle, culled or not.
  Scene s = light_only_scene();
  Pcg32 rng(41, 42);
  for (int k = 0; k < 120; ++k) {
    const Vec3 c(-0.6f + 1.2f * rng.next_float(), 0.6f + 0.8f * rng.next_float(),
                 -0.6f + 1.2f * rng.next_float());
    Mesh m = k % 2 == 0 ? make_sphere(c, 0.04f + 0.05f * rng.next_float(), 8, 12)
                        : make_box(c, Vec3(0.03f + 0.04f * rng.next_float()));
    m.material = 0;
    s.meshes.push_back(std::move(m));
  }
  const ExactScene culled(s, 4, true), full(s, 4, false);
  const ExactLight light(s, s.lights[0]);
  int crowded = 0;
  double max_diff = 0.0;
  for (int k = 0; k < 12; ++k) {
    const Vec3 p(-0.5f + 1.0f * rng.next_float(), 0.0f, -0.5f + 1.0f * rng.next_float());
    const double direct = direct_union_visibility(full, s.lights[0], light, p);
    for (const ExactScene* scene : {&culled, &full}) {
      const ExactPointResult r = exact_visibility(*scene, light, p);
      max_diff = std::max(max_diff, std::abs(r.visible - direct));
      EXPECT_NEAR(r.visible, direct, 1e-9) << "receiver " << k;
      crowded += r.polygons > 1000 ? 1 : 0;
    }
  }
  // Measured: every receiver over 1 000 polygons, 23 of the 24 sweeps divided (400–1 000 edges).
  std::printf("many meshes: %d of 24 with > 1000 polygons, max |V - direct union| %.3g\n", crowded,
              max_diff);
  EXPECT_GE(crowded, 20);
}

TEST(Exact, TraceLoopsDropsCancelledPairsAndCollinearVertices) {
  // Two unit squares sharing an edge, given as edges (one copy of the shared edge each way), plus
  // a collinear midpoint on the outline: one loop of 4 corners, the union's area.
  using ClipperLib::IntPoint;
  std::vector<DirectedEdge> edges = {
      {{0, 0}, {5, 0}},    {{5, 0}, {10, 0}},    {{10, 0}, {10, 10}},
      {{10, 10}, {0, 10}}, {{0, 10}, {0, 0}},    {{10, 0}, {20, 0}},
      {{20, 0}, {20, 10}}, {{20, 10}, {10, 10}}, {{10, 10}, {10, 0}}};
  ClipperLib::Paths loops;
  const size_t count = trace_loops(edges, loops);
  ASSERT_EQ(count, 1u);
  EXPECT_EQ(loops[0].size(), 4u);
  EXPECT_DOUBLE_EQ(ClipperLib::Area(loops[0]), 200.0);
}

TEST(Exact, SemiOpaqueSpheresMatchBruteForce) {
  // Closed semi-opaque meshes: each ray crosses a sphere twice (t²), overlapping spheres
  // multiply further; two transmittance values exercise the grouping.
  Scene s = make_builtin_scene("spheres");
  Mesh second = s.meshes[1];
  s.materials[s.meshes[1].material].transmittance = 0.6f;
  second.material = add_material(s, 0.8f);
  for (Vec3& v : second.positions) v += Vec3(0.13f, 0.25f, 0.07f);
  s.meshes.push_back(second);
  const ExactScene es(s);
  for (const Vec3 p : {Vec3(0.35f, 0.0f, 0.25f), Vec3(0.1f, 0.0f, -0.3f)}) {
    const double e = exact_visible_fraction(es, s.lights[0], p),
                 b = brute_force(s, s.lights[0], p, 96);
    EXPECT_NEAR(e, b, 3e-3);
    std::printf("semi-opaque spheres: exact %.6f brute force (96²) %.6f\n", e, b);
  }
}

TEST(Exact, RegisteredWithOptions) {
  MethodRegistry registry;
  register_exact(registry);
  const MethodInfo* info = registry.find("exact");
  ASSERT_NE(info, nullptr);
  EXPECT_FALSE(info->sample_exact);  // analytic, not sample-equal to raytrace
  const MethodOptions o = resolve_options(*info, {{"disk_segments", "64"}});
  EXPECT_EQ(o.get_int("disk_segments"), 64);
  EXPECT_EQ(o.get_int("leaf_size"), 8);
  EXPECT_NE(info->create(o), nullptr);
}

// ---------------------------------------------------------------------------------------------
// Whole frame: G-buffer (Embree) → receivers → exact, on the quad scene.

TEST(ExactFrame, QuadGroundPixelsMatchTheClosedForm) {
  Scene s = make_builtin_scene("quad");
  s.camera.width = 64;
  s.camera.height = 64;
  const EmbreeScene embree(s);
  const GBuffer g = render_gbuffer(embree, s.camera);
  const Image<uint8_t> receivers = classify_receivers(g, s.lights[0]);
  LightSampleSpec spec;
  spec.k = 1;
  const LightSamples samples(spec);
  const ShadowContext ctx{s, nullptr, g, 0, s.lights[0], samples, receivers, false};
  const std::unique_ptr<ShadowMethod> method = make_exact_method();
  const Visibility v = method->compute(ctx);
  int checked = 0, penumbra = 0;
  double offset_effect = 0.0;
  for (size_t i = 0; i < g.pixel_count(); ++i) {
    if (receivers[i] != kActive || s.meshes[g.mesh_id[i]].name != "ground") continue;
    const Vec3 p = g.shadow_origin(i);  // ray_offset above the ground: the generalised form
    const double closed = quad_scene_visible_fraction(p.x, p.y, p.z);
    EXPECT_NEAR(v.lit[i], closed, 1e-5) << "pixel " << i;
    offset_effect =
        std::max(offset_effect, std::abs(closed - quad_scene_visible_fraction(p.x, p.z)));
    ++checked;
    penumbra += closed > 0.0 && closed < 1.0;
  }
  EXPECT_GT(checked, 1000);
  EXPECT_GT(penumbra, 100);
  std::printf(
      "quad frame: %d ground pixels, ray offset %.3g moves V by up to %.3g vs the y = 0 form\n",
      checked, g.ray_offset[g.pixel_count() / 2], offset_effect);
  EXPECT_GT(v.counters.at("pixels"), 0.0);
  EXPECT_GT(v.counters.at("pixels_penumbra"), 0.0);
  EXPECT_GT(v.counters.at("pixels_umbra"), 0.0);
  EXPECT_EQ(v.counters.at("degenerate_fallbacks"), 0.0);
  EXPECT_GT(v.times.get("visibility"), 0.0);
  EXPECT_FALSE(v.lit_rgb.has_value());
}

Visibility run_exact_frame(Scene& s, int size) {
  s.camera.width = size;
  s.camera.height = size;
  const EmbreeScene embree(s);
  const GBuffer g = render_gbuffer(embree, s.camera);
  const Image<uint8_t> receivers = classify_receivers(g, s.lights[0]);
  LightSampleSpec spec;
  spec.k = 1;
  const LightSamples samples(spec);
  const ShadowContext ctx{s, nullptr, g, 0, s.lights[0], samples, receivers, false};
  return make_exact_method()->compute(ctx);
}

void report(const char* what, const Visibility& v) {
  std::printf(
      "%s: bvh %.2f ms, visibility %.2f ms, %g pixels (%g lit, %g umbra, %g penumbra), "
      "%.1f candidates/pixel (max %g), %g alpha pieces\n",
      what, v.times.get("bvh"), v.times.get("visibility"), v.counters.at("pixels"),
      v.counters.at("pixels_lit"), v.counters.at("pixels_umbra"), v.counters.at("pixels_penumbra"),
      v.counters.at("candidates_per_pixel"), v.counters.at("candidates_max"),
      v.counters.at("alpha_pieces"));
}

/// Cost per pixel (reported, never asserted: speed belongs in benchmarks).
TEST(ExactFrame, CostReport) {
  Scene spheres = make_builtin_scene("spheres");
  const Visibility v = run_exact_frame(spheres, 128);
  report("spheres 128x128", v);
  EXPECT_GT(v.counters.at("pixels_penumbra"), 0.0);
  Scene fence = make_builtin_scene("fence");
  report("fence 128x128", run_exact_frame(fence, 128));
  if (find_model("bunny00.off")) {
    Scene bunny = make_builtin_scene("bunny");
    report("bunny 128x128", run_exact_frame(bunny, 128));
  }
  Scene semi = make_builtin_scene("spheres");
  semi.materials[semi.meshes[1].material].transmittance = 0.5f;
  report("semi-opaque spheres 64x64", run_exact_frame(semi, 64));
}

TEST(ExactFrame, TexturedLightFillsLitRgb) {
  Scene s = make_builtin_scene("quad");
  Texture t;
  t.name = "stripes";
  t.width = 4;
  t.height = 2;
  t.channels = 3;
  for (int k = 0; k < 8; ++k) {
    t.texels.push_back(k % 2 ? 1.0f : 0.2f);
    t.texels.push_back(0.5f);
    t.texels.push_back(k % 3 ? 0.1f : 0.9f);
  }
  s.textures.push_back(t);
  s.lights[0].emission_texture = 0;
  const Visibility v = run_exact_frame(s, 32);
  ASSERT_TRUE(v.lit_rgb.has_value());
  bool coloured = false;
  for (size_t i = 0; i < v.lit.size(); ++i) {
    const Vec3 c = (*v.lit_rgb)[i];
    EXPECT_TRUE(is_finite(c));
    coloured = coloured || std::abs(c.x - c.z) > 0.01f;
  }
  EXPECT_TRUE(coloured);
}

}  // namespace
}  // namespace penumbra
