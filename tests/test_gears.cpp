// GEARS [Wang 2014]: same samples, same answer as `raytrace` — per-sample masks on whole frames,
// conservative candidate sets (brute force), the point-light limit, alpha and semi-opaque
// occluders, round lights, irregular sample patterns, and the LUT variant's error.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>

#include "penumbra/render/receivers.hpp"
#include "penumbra/scene/model_paths.hpp"
#include "penumbra/scene/shapes.hpp"
#include "penumbra/shadows/gears/item_cull.hpp"
#include "support/frame_helpers.hpp"

namespace penumbra {
namespace {

using test::make_test_frame;
using test::TestFrame;

LightSampleSpec pattern(SamplePattern p, int k) {
  LightSampleSpec s;
  s.pattern = p;
  s.k = k;
  s.seed = 7;
  return s;
}
LightSampleSpec grid(int k) {
  return pattern(SamplePattern::grid, k);
}

/// Is the segment origin → x numerically ambiguous against some occluding triangle: within a
/// relative `tol` of one of its edge planes or of its plane (t = 1)? Double precision, brute force.
bool ambiguous(const Scene& scene, const DVec3& o, const DVec3& x, double tol = 1e-4) {
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
    }
  }
  return false;
}

struct MaskAgreement {
  uint64_t pairs = 0, differ = 0, unexplained = 0;
  double mean_abs_dv = 0.0;
  int blocked = 0;
};

/// Compares gears's masks with raytrace's on every active pixel; classifies each mismatch.
MaskAgreement compare_masks(const TestFrame& t,
                            const std::map<std::string, std::string>& options = {},
                            bool classify = true) {
  const MethodResult rt = t.run("raytrace", {}, true);
  const MethodResult ge = t.run("gears", options, true);
  const SampleMasks& mr = *rt.per_light[0].masks;
  const SampleMasks& mg = *ge.per_light[0].masks;
  const GBuffer& g = t.frame->gbuffer();
  const int n = t.frame->samples().count();
  MaskAgreement out;
  std::vector<Vec2> uv(n);
  size_t active = 0;
  for (size_t i = 0; i < g.pixel_count(); ++i) {
    if (t.frame->receivers(0)[i] != kActive) continue;
    ++active;
    out.mean_abs_dv += std::abs(rt.per_light[0].lit[i] - ge.per_light[0].lit[i]);
    for (int s = 0; s < n; ++s) {
      ++out.pairs;
      out.blocked += mr.blocked(i, s);
      if (mr.blocked(i, s) == mg.blocked(i, s)) continue;
      ++out.differ;
      if (!classify) continue;
      t.frame->samples().pixel_samples(static_cast<int>(i % g.width), static_cast<int>(i / g.width),
                                       uv);
      const Vec3 o = g.shadow_origin(i);
      const Vec3 x = light_frame(t.scene->lights[0], o).point(uv[s]);
      if (!ambiguous(*t.scene, DVec3(o), DVec3(x))) {
        ++out.unexplained;
        if (out.unexplained <= 5)
          std::printf("unexplained mismatch: pixel %zu sample %d raytrace %d gears %d\n", i, s,
                      int(mr.blocked(i, s)), int(mg.blocked(i, s)));
      }
    }
  }
  out.mean_abs_dv /= std::max<size_t>(1, active);
  return out;
}

void expect_equal_masks(const MaskAgreement& a, int min_blocked = 100) {
  std::printf(
      "masks: %llu pairs, %d blocked, %llu differ (%.5f%%), %llu unexplained, mean |dV| %.2e\n",
      static_cast<unsigned long long>(a.pairs), a.blocked,
      static_cast<unsigned long long>(a.differ), 100.0 * a.differ / std::max<uint64_t>(1, a.pairs),
      static_cast<unsigned long long>(a.unexplained), a.mean_abs_dv);
  EXPECT_GT(a.blocked, min_blocked);
  EXPECT_LE(static_cast<double>(a.differ), 1e-3 * a.pairs) << a.differ << " of " << a.pairs;
  EXPECT_EQ(a.unexplained, 0u) << "mismatches not on a triangle edge within float tolerance";
  EXPECT_LE(a.mean_abs_dv, 1e-3);
}

TEST(Gears, MasksEqualRaytraceOnQuad) {
  expect_equal_masks(compare_masks(make_test_frame("quad", 64, 64, grid(16))));
}

TEST(Gears, MasksEqualRaytraceOnSpheres) {
  expect_equal_masks(compare_masks(make_test_frame("spheres", 64, 64, grid(16))));
}

TEST(Gears, MasksEqualRaytraceOnFenceWithAlpha) {
  expect_equal_masks(compare_masks(make_test_frame("fence", 64, 64, grid(16))));
}

/// A dynamic scene: the occluder moves between two frames; nothing is kept between them.
TEST(Gears, MasksEqualRaytraceWhenAnOccluderMoves) {
  Scene scene = make_builtin_scene("spheres");
  const auto before = make_test_frame(scene, 48, 48, grid(8));
  expect_equal_masks(compare_masks(before));
  for (Mesh& m : scene.meshes)
    if (m.name != "ground")
      for (Vec3& p : m.positions) p += Vec3(0.15f, 0.1f, -0.2f);
  expect_equal_masks(compare_masks(make_test_frame(std::move(scene), 48, 48, grid(8))));
}

TEST(Gears, MasksEqualRaytraceOnBunny) {
  if (!find_model("bunny00.off")) GTEST_SKIP() << "bunny not fetched: run scripts/fetch-models.sh";
  // Classification brute-forces 70k triangles per mismatch: only count here.
  const MaskAgreement a = compare_masks(make_test_frame("bunny", 48, 48, grid(16)), {}, false);
  std::printf("bunny masks: %llu pairs, %d blocked, %llu differ\n",
              static_cast<unsigned long long>(a.pairs), a.blocked,
              static_cast<unsigned long long>(a.differ));
  EXPECT_GT(a.blocked, 1000);
  EXPECT_LE(static_cast<double>(a.differ), 1e-3 * a.pairs) << a.differ << " of " << a.pairs;
  EXPECT_LE(a.mean_abs_dv, 1e-3);
}

/// Every option changes only the candidate sets, never the answer.
TEST(Gears, OptionsDoNotChangeTheAnswer) {
  const auto t = make_test_frame("spheres", 48, 48, grid(8));
  const MethodResult base = t.run("gears", {}, true);
  for (const auto& opts :
       std::vector<std::map<std::string, std::string>>{{{"grid", "1"}},
                                                       {{"grid", "300"}},
                                                       {{"retraction", "false"}},
                                                       {{"cell_depth_cull", "false"}},
                                                       {{"eye_distance", "0.1"}},
                                                       {{"eye_distance", "20"}},
                                                       {{"chunk", "1"}}}) {
    const MethodResult r = t.run("gears", opts, true);
    EXPECT_EQ(r.per_light[0].lit.pixels(), base.per_light[0].lit.pixels()) << opts.begin()->first;
  }
}

/// Conservativeness: brute force over all triangles (double precision segment tests) on a small
/// frame — no sample that some triangle blocks may be left lit, except on a numerical edge.
TEST(Gears, NeverMissesABlockingTriangle) {
  const auto t = make_test_frame("spheres", 20, 20, grid(4));
  const MethodResult ge = t.run("gears", {}, true);
  const SampleMasks& mg = *ge.per_light[0].masks;
  const GBuffer& g = t.frame->gbuffer();
  std::vector<Vec2> uv(16);
  t.frame->samples().pixel_samples(0, 0, uv);
  int missed = 0, blocked = 0;
  for (size_t i = 0; i < g.pixel_count(); ++i) {
    if (t.frame->receivers(0)[i] != kActive) continue;
    const DVec3 o(g.shadow_origin(i));
    for (int s = 0; s < 16; ++s) {
      const DVec3 x(light_frame(t.scene->lights[0], Vec3(o)).point(uv[s]));
      bool hit = false;
      for (const Mesh& m : t.scene->meshes)
        for (size_t tri = 0; tri < m.triangle_count() && !hit; ++tri)
          hit = test::segment_crosses_triangle(o, x - o, DVec3(m.vertex(tri, 0)),
                                               DVec3(m.vertex(tri, 1)), DVec3(m.vertex(tri, 2)));
      blocked += hit;
      if (hit && !mg.blocked(i, s) && !ambiguous(*t.scene, o, x)) ++missed;
    }
  }
  EXPECT_GT(blocked, 50);
  EXPECT_EQ(missed, 0);
}

/// The point-light limit: one bit per pixel, the hard shadow of `raytrace` (irregular z-buffer).
/// The per-work-item cull (gears/item_cull.hpp) never drops a triangle that blocks one of the
/// item's samples from some light point: random triangles and sample sets in light space, blocking
/// decided by a double-precision segment–triangle test against a 24×24 grid of light points.
TEST(Gears, ItemCullIsConservative) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> xy(-1.5f, 2.5f), tz(0.05f, 2.0f), sz(0.05f, 4.0f);
  gears::FlatLight light;
  light.flat = true, light.lx0 = light.ly0 = 0.0f, light.lx1 = light.ly1 = 1.0f;
  int blocking = 0, culled = 0;
  for (int trial = 0; trial < 3000; ++trial) {
    gears::TriangleSoup soup;
    soup.mesh = {0}, soup.prim = {0}, soup.opaque = {1};
    DVec3 v[3];
    for (int c = 0; c < 3; ++c) {
      v[c] = DVec3(xy(rng), xy(rng), tz(rng));
      soup.x[c] = {float(v[c].x)}, soup.y[c] = {float(v[c].y)}, soup.z[c] = {float(v[c].z)};
    }
    const std::vector<float> zmin = {std::min({soup.z[0][0], soup.z[1][0], soup.z[2][0]})};
    const gears::PackedTriangle tri = gears::pack_triangles(soup, +1, zmin, light)[0];
    // A small cluster of samples, like a work item's.
    const Vec3 centre(xy(rng), xy(rng), sz(rng));
    float px[8], py[8], pz[8];
    for (int i = 0; i < 8; ++i)
      px[i] = centre.x + 0.1f * xy(rng), py[i] = centre.y + 0.1f * xy(rng),
      pz[i] = std::max(0.05f, centre.z + 0.1f * xy(rng));
    const bool kept = gears::may_block(tri, gears::item_bounds(light, px, py, pz, 8));
    culled += !kept;
    bool blocks = false;
    for (int i = 0; i < 8 && !blocks; ++i)
      for (int a = 0; a < 24 * 24 && !blocks; ++a) {
        const DVec3 o(px[i], py[i], pz[i]);
        const DVec3 d = DVec3((a % 24 + 0.5) / 24, (a / 24 + 0.5) / 24, 0.0) - o;
        const DVec3 e1 = v[1] - v[0], e2 = v[2] - v[0], q = glm::cross(d, e2);
        const double det = glm::dot(e1, q);
        if (std::abs(det) < 1e-12) continue;
        const DVec3 w = o - v[0];
        const double bu = glm::dot(w, q) / det;
        const DVec3 r = glm::cross(w, e1);
        const double bv = glm::dot(d, r) / det, t = glm::dot(e2, r) / det;
        blocks = bu >= 0 && bv >= 0 && bu + bv <= 1 && t > 0 && t < 1;
      }
    blocking += blocks;
    if (blocks) {
      EXPECT_TRUE(kept) << "trial " << trial;
    }
  }
  std::printf("item cull: %d of 3000 random triangles block, %d culled\n", blocking, culled);
  EXPECT_GT(blocking, 100);
  EXPECT_GT(culled, 1000);
}

TEST(Gears, PointLightGivesTheHardShadow) {
  Scene scene = make_builtin_scene("spheres");
  scene.lights[0].shape = LightShape::point;
  const auto t = make_test_frame(std::move(scene), 64, 64, grid(1));
  const MaskAgreement a = compare_masks(t);
  EXPECT_GT(a.blocked, 100);
  EXPECT_LE(static_cast<double>(a.differ), 1e-3 * a.pairs);
  EXPECT_EQ(a.unexplained, 0u);
}

TEST(Gears, SemiOpaqueOccluderMatchesRaytrace) {
  Scene scene = make_builtin_scene("spheres");
  Material glass;
  glass.name = "glass";
  glass.transmittance = 0.5f;
  scene.materials.push_back(glass);
  for (Mesh& m : scene.meshes)
    if (m.name != "ground") m.material = static_cast<int>(scene.materials.size() - 1);
  const auto t = make_test_frame(std::move(scene), 48, 48, grid(8));
  const MethodResult rt = t.run("raytrace");
  const MethodResult ge = t.run("gears");
  double diff = 0.0, max_diff = 0.0;
  int partial = 0;
  for (size_t i = 0; i < rt.per_light[0].lit.size(); ++i) {
    const double d = std::abs(rt.per_light[0].lit[i] - ge.per_light[0].lit[i]);
    diff += d;
    max_diff = std::max(max_diff, d);
    partial += rt.per_light[0].lit[i] > 0.01f && rt.per_light[0].lit[i] < 0.99f;
  }
  EXPECT_GT(partial, 100);
  EXPECT_LE(diff / rt.per_light[0].lit.size(), 1e-3);
}

TEST(Gears, DiskAndSphereLightsMatchRaytrace) {
  for (LightShape shape : {LightShape::disk, LightShape::sphere}) {
    Scene scene = make_builtin_scene("spheres");
    Light& l = scene.lights[0];
    l.shape = shape;
    l.radius = 0.4f;
    l.normal = Vec3(0, -1, 0);
    expect_equal_masks(compare_masks(make_test_frame(std::move(scene), 48, 48, grid(8))));
  }
}

/// Irregular samples: the edge-plane variant tests every sample (row spans need the grid).
TEST(Gears, IrregularPatternsMatchRaytrace) {
  for (SamplePattern p :
       {SamplePattern::stratified, SamplePattern::decorrelated, SamplePattern::halton})
    expect_equal_masks(compare_masks(make_test_frame("spheres", 40, 40, pattern(p, 8))));
}

/// Table 4 of the paper: the LUT variant's error against edge planes (max and mean per pixel).
TEST(Gears, LutVariantErrorIsSmall) {
  const auto t = make_test_frame("spheres", 64, 64, grid(16));
  const MethodResult edge = t.run("gears");
  const MethodResult lut = t.run("gears", {{"variant", "lut"}, {"lut_resolution", "512"}});
  double mean = 0.0, max = 0.0;
  for (size_t i = 0; i < edge.per_light[0].lit.size(); ++i) {
    const double d = std::abs(edge.per_light[0].lit[i] - lut.per_light[0].lit[i]);
    mean += d;
    max = std::max(max, d);
  }
  mean /= edge.per_light[0].lit.size();
  std::printf("LUT vs edge planes: max %.4f mean %.5f\n", max, mean);
  EXPECT_LE(mean, 0.01);
  EXPECT_LE(max, 0.1);
}

TEST(Gears, ReportsThePaperStatistics) {
  const auto t = make_test_frame("spheres", 48, 48, grid(8));
  const Visibility v = t.run("gears").per_light[0];
  for (const char* key : {"pairs", "pairs_without_retraction", "triangles_per_cell_max",
                          "triangles_per_cell_avg", "samples_per_cell_max", "samples_per_cell_avg",
                          "assignments_total", "assignments_necessary", "memory_bytes"})
    EXPECT_TRUE(v.counters.count(key)) << key;
  EXPECT_LE(v.counters.at("pairs"), v.counters.at("pairs_without_retraction"));
  EXPECT_LE(v.counters.at("assignments_necessary"), v.counters.at("assignments_total"));
  for (const char* stage : {"project_pixels", "count_prefix_sum", "write_pairs", "sort_pairs",
                            "bitmask_rasterization", "shading"})
    EXPECT_GE(v.times.get(stage), 0.0) << stage;
}

}  // namespace
}  // namespace penumbra
