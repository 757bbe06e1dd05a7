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
#include "penumbra/shadows/gears/raster.hpp"
#include "support/frame_helpers.hpp"
#include "support/mask_agreement.hpp"

namespace penumbra {
namespace {

using test::ambiguous;
using test::expect_equal_masks;
using test::make_test_frame;
using test::MaskAgreement;
using test::TestFrame;

LightSampleSpec pattern(SamplePattern p, int k) {
  return test::sample_spec(p, k, 7);
}
using test::grid_samples;

/// gears's masks against raytrace's (support/mask_agreement.hpp).
MaskAgreement compare_masks(const TestFrame& t,
                            const std::map<std::string, std::string>& options = {},
                            bool classify = true) {
  return test::compare_masks(t, "gears", options, classify);
}

TEST(Gears, MasksEqualRaytraceOnQuad) {
  expect_equal_masks(compare_masks(make_test_frame("quad", 64, 64, grid_samples(16))));
}

TEST(Gears, MasksEqualRaytraceOnSpheres) {
  expect_equal_masks(compare_masks(make_test_frame("spheres", 64, 64, grid_samples(16))));
}

TEST(Gears, MasksEqualRaytraceOnFenceWithAlpha) {
  expect_equal_masks(compare_masks(make_test_frame("fence", 64, 64, grid_samples(16))));
}

/// A dynamic scene: the occluder moves between two frames; nothing is kept between them.
TEST(Gears, MasksEqualRaytraceWhenAnOccluderMoves) {
  Scene scene = make_builtin_scene("spheres");
  const auto before = make_test_frame(scene, 48, 48, grid_samples(8));
  expect_equal_masks(compare_masks(before));
  for (Mesh& m : scene.meshes)
    if (m.name != "ground")
      for (Vec3& p : m.positions) p += Vec3(0.15f, 0.1f, -0.2f);
  expect_equal_masks(compare_masks(make_test_frame(std::move(scene), 48, 48, grid_samples(8))));
}

TEST(Gears, MasksEqualRaytraceOnBunny) {
  if (!find_model("bunny00.off")) GTEST_SKIP() << "bunny not fetched: run scripts/fetch-models.sh";
  // Measured: 0 of 463 104 (pixel, sample) pairs differ. Classification brute-forces 70k
  // triangles per mismatch, so at most a handful are allowed (rounding on a triangle edge may
  // differ between instruction sets), and each must be explained.
  const MaskAgreement a =
      compare_masks(make_test_frame("bunny", 48, 48, grid_samples(16)), {}, true);
  std::printf("bunny masks: %llu pairs, %d blocked, %llu differ, %llu unexplained\n",
              static_cast<unsigned long long>(a.pairs), a.blocked,
              static_cast<unsigned long long>(a.differ),
              static_cast<unsigned long long>(a.unexplained));
  EXPECT_GT(a.blocked, 10000);
  EXPECT_LE(a.differ, 5u) << a.differ << " of " << a.pairs;
  EXPECT_EQ(a.unexplained, 0u);
  EXPECT_LE(a.mean_abs_dv, 1e-5);
}

/// Every option changes only the candidate sets, never the answer.
TEST(Gears, OptionsDoNotChangeTheAnswer) {
  const auto t = make_test_frame("spheres", 48, 48, grid_samples(8));
  const MethodResult base = t.run("gears", {}, true);
  for (const auto& opts :
       std::vector<std::map<std::string, std::string>>{{{"grid", "1"}},
                                                       {{"grid", "300"}},
                                                       {{"retraction", "false"}},
                                                       {{"cell_depth_cull", "false"}},
                                                       {{"eye_distance", "0.1"}},
                                                       {{"eye_distance", "20"}},
                                                       {{"chunk", "1"}},
                                                       {{"pixel_cull", "false"}}}) {
    const MethodResult r = t.run("gears", opts, true);
    EXPECT_EQ(r.per_light[0].lit.pixels(), base.per_light[0].lit.pixels()) << opts.begin()->first;
  }
}

/// Conservativeness: brute force over all triangles (double precision segment tests) on a small
/// frame — no sample that some triangle blocks may be left lit, except on a numerical edge.
TEST(Gears, NeverMissesABlockingTriangle) {
  const auto t = make_test_frame("spheres", 20, 20, grid_samples(4));
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

/// One opaque triangle in light space, vertex coordinates drawn from xy (x, y) and z (depth).
gears::TriangleSoup random_triangle(std::mt19937& rng, std::uniform_real_distribution<float>& xy,
                                    std::uniform_real_distribution<float>& z, DVec3 v[3]) {
  gears::TriangleSoup soup;
  soup.mesh = {0}, soup.prim = {0}, soup.opaque = {1};
  for (int c = 0; c < 3; ++c) {
    v[c] = DVec3(xy(rng), xy(rng), z(rng));
    soup.x[c] = {float(v[c].x)}, soup.y[c] = {float(v[c].y)}, soup.z[c] = {float(v[c].z)};
  }
  return soup;
}

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
    DVec3 v[3];
    const gears::TriangleSoup soup = random_triangle(rng, xy, tz, v);
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

/// The per-pixel cull (CandidateBatch::keep: the slabs and depth cut for one sample, and the
/// separating-plane test) never drops a triangle that blocks the sample from some light point:
/// random triangles and samples in light space, a third of the samples within 10⁻³ of the
/// triangle's plane (the neighbours of a sample on a closed mesh), blocking decided in double
/// precision against 24×24 light points.
TEST(Gears, PixelCullIsConservative) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> xy(-1.5f, 2.5f), tz(0.05f, 2.0f), sz(0.05f, 4.0f),
      unit(0.0f, 1.0f);
  gears::FlatLight light;
  light.flat = true, light.lx0 = light.ly0 = 0.0f, light.lx1 = light.ly1 = 1.0f;
  gears::GridCamera cam;  // only its light corners matter for a flat light
  int blocking = 0, culled = 0, near_plane = 0;
  for (int trial = 0; trial < 4000; ++trial) {
    DVec3 v[3];
    const gears::TriangleSoup soup = random_triangle(rng, xy, tz, v);
    const std::vector<float> zmin = {std::min({soup.z[0][0], soup.z[1][0], soup.z[2][0]})};
    const auto packed = gears::pack_triangles(soup, +1, zmin, light);
    const auto planes = gears::triangle_planes(soup, gears::plane_test_corners(light, cam));
    DVec3 o(xy(rng), xy(rng), sz(rng));
    if (trial % 3 == 0) {
      // Near the triangle's plane, on either side, above or beside the triangle.
      const DVec3 n = glm::normalize(glm::cross(v[1] - v[0], v[2] - v[0]));
      const double a = unit(rng) * 1.6 - 0.3, b = unit(rng) * (1.3 - a);
      o = v[0] + a * (v[1] - v[0]) + b * (v[2] - v[0]) + n * (unit(rng) * 2e-3 - 1e-3);
      if (!(o.z > 0.01)) continue;
      ++near_plane;
    }
    const Vec3 p(o);
    const float pz = p.z;
    const gears::CellPair pair{0, 0};
    gears::CandidateBatch item, pixel;
    const gears::ItemBounds bounds = gears::item_bounds(light, &p.x, &p.y, &pz, 1);
    item.gather(packed.data(), planes.data(), &pair, &pair + 1, bounds);
    pixel.keep(item, 0, item.count, bounds, p);
    const bool kept = pixel.count == 1;
    culled += !kept;
    bool blocks = false;
    for (int s = 0; s < 24 * 24 && !blocks; ++s) {
      const DVec3 x((s % 24 + 0.5) / 24, (s / 24 + 0.5) / 24, 0.0);
      blocks = test::segment_crosses_triangle(DVec3(p), x - DVec3(p), v[0], v[1], v[2]);
    }
    blocking += blocks;
    if (blocks) {
      EXPECT_TRUE(kept) << "trial " << trial;
    }
  }
  std::printf("pixel cull: %d samples near the plane, %d of 4000 triangles block, %d culled\n",
              near_plane, blocking, culled);
  EXPECT_GT(blocking, 100);
  EXPECT_GT(culled, 2000);
  EXPECT_GT(near_plane, 1000);
}

/// The point-light limit: one bit per pixel, the hard shadow of `raytrace` (irregular z-buffer).
TEST(Gears, PointLightGivesTheHardShadow) {
  Scene scene = make_builtin_scene("spheres");
  scene.lights[0].shape = LightShape::point;
  const auto t = make_test_frame(std::move(scene), 64, 64, grid_samples(1));
  const MaskAgreement a = compare_masks(t);
  EXPECT_GT(a.blocked, 100);
  EXPECT_LE(static_cast<double>(a.differ), 1e-3 * a.pairs);
  EXPECT_EQ(a.unexplained, 0u);
}

/// The spheres scene with every sphere semi-opaque (transmittance 0.5), or opaque.
Scene glass_spheres(bool semi_opaque) {
  Scene scene = make_builtin_scene("spheres");
  Material glass;
  glass.name = "glass";
  glass.transmittance = semi_opaque ? 0.5f : 0.0f;
  scene.materials.push_back(glass);
  for (Mesh& m : scene.meshes)
    if (m.name != "ground") m.material = static_cast<int>(scene.materials.size() - 1);
  return scene;
}

TEST(Gears, SemiOpaqueOccluderMatchesRaytrace) {
  const auto t = make_test_frame(glass_spheres(true), 48, 48, grid_samples(8));
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

/// Semi-opaque occluders need per-sample transmittances only while their pixel is rasterized:
/// the memory they add is one n-float buffer per thread, not frame × samples (here that would be
/// ≈ 3.5 MB: ~3 500 active pixels × 256 samples × 4 bytes).
TEST(Gears, SemiOpaqueMemoryIsPerWorkItem) {
  const auto glass = make_test_frame(glass_spheres(true), 64, 64, grid_samples(16));
  const auto opaque = make_test_frame(glass_spheres(false), 64, 64, grid_samples(16));
  const double with = glass.run("gears").per_light[0].counters.at("memory_bytes");
  const double without = opaque.run("gears").per_light[0].counters.at("memory_bytes");
  const double per_thread = 256.0 * sizeof(float);
  std::printf("memory: semi-opaque %.0f bytes, opaque %.0f bytes\n", with, without);
  EXPECT_GE(with - without, per_thread);
  EXPECT_LE(with - without, 64 * per_thread);  // at most 64 threads' buffers
}

TEST(Gears, DiskAndSphereLightsMatchRaytrace) {
  for (LightShape shape : {LightShape::disk, LightShape::sphere}) {
    Scene scene = make_builtin_scene("spheres");
    Light& l = scene.lights[0];
    l.shape = shape;
    l.radius = 0.4f;
    l.normal = Vec3(0, -1, 0);
    expect_equal_masks(compare_masks(make_test_frame(std::move(scene), 48, 48, grid_samples(8))));
  }
}

/// A sphere light in the middle of a room: samples on the walls beside the light lie within its
/// depth slab, where a blocker can be deeper than the sample (the light reaches behind it). Every
/// mask must still equal raytrace's; one semi-opaque sphere checks the transmittance path too.
Scene sphere_light_in_a_room() {
  Scene s;
  s.name = "sphere_light_in_a_room";
  Material grey, glass;
  grey.name = "grey";
  glass.name = "glass";
  glass.transmittance = 0.4f;
  s.materials = {grey, glass};
  auto add = [&](Mesh m, const char* name, int material) {
    m.name = name;
    m.material = material;
    s.meshes.push_back(std::move(m));
  };
  add(make_quad(Vec3(0, 0, 0), Vec3(0, 0, 8), Vec3(8, 0, 0)), "ground", 0);
  add(make_quad(Vec3(0, 3, 0), Vec3(8, 0, 0), Vec3(0, 0, 8)), "ceiling", 0);
  add(make_quad(Vec3(0, 1.5f, -2), Vec3(8, 0, 0), Vec3(0, 3, 0)), "wall", 0);
  add(make_sphere(Vec3(-0.7f, 0.6f, 0), 0.3f, 16, 32), "s1", 0);
  add(make_sphere(Vec3(0.6f, 2.2f, 0.2f), 0.25f, 16, 32), "s2", 1);
  add(make_sphere(Vec3(0.2f, 1.4f, -0.9f), 0.25f, 16, 32), "s3", 0);
  add(make_box(Vec3(-0.5f, 1.5f, 0.5f), Vec3(0.1f, 0.4f, 0.1f)), "b", 0);
  Light light;
  light.shape = LightShape::sphere;
  light.center = Vec3(0, 1.5f, 0);
  light.radius = 0.3f;
  light.radiance = Vec3(5.0f);
  s.lights.push_back(light);
  s.camera.position = Vec3(0, 1.2f, 5);
  s.camera.target = Vec3(0, 1.2f, 0);
  s.camera.vfov_deg = 70.0f;
  return s;
}

TEST(Gears, SphereLightAmongOccludersMatchesRaytrace) {
  const auto t = make_test_frame(sphere_light_in_a_room(), 64, 64, grid_samples(8));
  const MaskAgreement a = compare_masks(t);
  expect_equal_masks(a);
  EXPECT_EQ(a.differ, 0u);
  // Per-pixel V (opaque bits and the glass sphere's transmittance) as raytrace's.
  const MethodResult rt = t.run("raytrace"), ge = t.run("gears");
  double max_dv = 0.0;
  for (size_t i = 0; i < rt.per_light[0].lit.size(); ++i)
    max_dv = std::max(max_dv, double(std::abs(rt.per_light[0].lit[i] - ge.per_light[0].lit[i])));
  std::printf("sphere light in a room: max |dV| %.2e\n", max_dv);
  EXPECT_LE(max_dv, 1e-5);
}

/// Irregular samples: the edge-plane variant tests every sample (row spans need the grid).
TEST(Gears, IrregularPatternsMatchRaytrace) {
  for (SamplePattern p :
       {SamplePattern::stratified, SamplePattern::decorrelated, SamplePattern::halton})
    expect_equal_masks(compare_masks(make_test_frame("spheres", 40, 40, pattern(p, 8))));
}

/// Table 4 of the paper: the LUT variant's error against edge planes (max and mean per pixel).
TEST(Gears, LutVariantErrorIsSmall) {
  const auto t = make_test_frame("spheres", 64, 64, grid_samples(16));
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
  // Measured: max 0.0117 (3 of 256 samples), mean 0.00043.
  EXPECT_LE(mean, 0.0006);
  EXPECT_LE(max, 0.016);
  EXPECT_GT(mean, 0.0);  // the LUT is an approximation: it must not be the edge-plane path
}

TEST(Gears, ReportsThePaperStatistics) {
  const auto t = make_test_frame("spheres", 48, 48, grid_samples(8));
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

// The item batch is in depth order, so each pixel's depth cut is a prefix of it and the per-pixel
// cull scans only that: fewer candidates than the item kept (a full scan would read them all),
// never fewer than it sets up.
TEST(Gears, PerPixelCullScansOnlyTheDepthPrefix) {
  const auto t = make_test_frame("spheres", 64, 64, grid_samples(16));
  const Visibility v = t.run("gears").per_light[0];
  const double item = v.counters.at("assignments_item");
  const double scanned = v.counters.at("pixel_cull_reads");
  std::printf("item candidates %.0f, scanned per pixel %.0f (%.3f), set up %.0f\n", item, scanned,
              scanned / item, v.counters.at("assignments_total"));
  EXPECT_LE(scanned, 0.95 * item);  // measured 0.911
  EXPECT_GE(scanned, v.counters.at("assignments_total"));
}

}  // namespace
}  // namespace penumbra
