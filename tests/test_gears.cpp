// GEARS [Wang 2014]: same samples, same answer as `raytrace` — per-sample masks on whole frames,
// conservative candidate sets (brute force), the point-light limit, alpha and semi-opaque
// occluders, round lights, irregular sample patterns, and the LUT variant's error.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdio>
#include <random>

#include "penumbra/render/receivers.hpp"
#include "penumbra/scene/model_paths.hpp"
#include "penumbra/scene/shapes.hpp"
#include "penumbra/shadows/gears/assign.hpp"
#include "penumbra/shadows/gears/item_cull.hpp"
#include "penumbra/shadows/gears/raster.hpp"
#include "penumbra/shadows/gears/solids.hpp"
#include "support/frame_helpers.hpp"
#include "support/gears_batch.hpp"
#include "support/mask_agreement.hpp"

namespace penumbra {
namespace {

using test::ambiguous;
using test::expect_equal_masks;
using test::make_test_frame;
using test::MaskAgreement;
using test::round_light_scene;
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
                                                       {{"pixel_cull", "false"}},
                                                       {{"group", "0"}},
                                                       {{"hidden_cull", "false"}},
                                                       {{"deepest_first", "false"}},
                                                       {{"box_cull", "false"}},
                                                       {{"solid_cull", "false"}},
                                                       {{"long_chunk", "1"}}}) {
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

/// `count` random triangles (random_triangle), each shrunk towards its first vertex by a factor
/// drawn from [shrink_lo, shrink_lo + shrink_span): small ones, like a dense mesh's.
gears::TriangleSoup small_random_triangles(std::mt19937& rng,
                                           std::uniform_real_distribution<float>& xy,
                                           std::uniform_real_distribution<float>& z, int count,
                                           float shrink_lo, float shrink_span) {
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  gears::TriangleSoup soup;
  for (int t = 0; t < count; ++t) {
    DVec3 v[3];
    const gears::TriangleSoup one = random_triangle(rng, xy, z, v);
    const float shrink = shrink_lo + shrink_span * unit(rng);
    soup.mesh.push_back(0), soup.prim.push_back(t), soup.opaque.push_back(1);
    for (int c = 0; c < 3; ++c) {
      soup.x[c].push_back(one.x[0][0] + shrink * (one.x[c][0] - one.x[0][0]));
      soup.y[c].push_back(one.y[0][0] + shrink * (one.y[c][0] - one.y[0][0]));
      soup.z[c].push_back(one.z[0][0] + shrink * (one.z[c][0] - one.z[0][0]));
    }
  }
  return soup;
}

/// A one-triangle soup's cull bounds (pack_triangles) under `light`.
gears::PackedTriangle packed_one(const gears::TriangleSoup& soup, const gears::FlatLight& light) {
  const std::vector<float> zmin = {std::min({soup.z[0][0], soup.z[1][0], soup.z[2][0]})};
  return gears::pack_triangles(soup, +1, zmin, light)[0];
}

/// The unit light square at z = 0, as FlatLight.
gears::FlatLight unit_light() {
  gears::FlatLight light;
  light.flat = true, light.lx0 = light.ly0 = 0.0f, light.lx1 = light.ly1 = 1.0f;
  return light;
}

/// The per-work-item cull (gears/item_cull.hpp) never drops a triangle that blocks one of the
/// item's samples from some light point: random triangles and sample sets in light space, blocking
/// decided by a double-precision segment–triangle test against a 24×24 grid of light points.
TEST(Gears, ItemCullIsConservative) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> xy(-1.5f, 2.5f), tz(0.05f, 2.0f), sz(0.05f, 4.0f);
  const gears::FlatLight light = unit_light();
  int blocking = 0, culled = 0;
  for (int trial = 0; trial < 3000; ++trial) {
    DVec3 v[3];
    const gears::TriangleSoup soup = random_triangle(rng, xy, tz, v);
    const gears::PackedTriangle tri = packed_one(soup, light);
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

/// A mesh box's cull bounds (gears::box_cull_bounds) keep every sample that one of its triangles'
/// own bounds keep: random triangles, each boxed as tightly as floats allow (its vertices' box, so
/// corners coincide with vertices), and random samples, a third of them near the triangle.
TEST(Gears, BoxCullBoundsKeepWhatTheirTrianglesKeep) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> xy(-1.5f, 2.5f), tz(0.05f, 2.0f), sz(0.05f, 4.0f);
  const gears::FlatLight light = unit_light();
  int kept_by_triangle = 0, culled_by_box = 0;
  for (int trial = 0; trial < 20000; ++trial) {
    DVec3 v[3];
    const gears::TriangleSoup soup = random_triangle(rng, xy, tz, v);
    const gears::PackedTriangle tri = packed_one(soup, light);
    Vec3 lo(kInfinity), hi(-kInfinity);
    for (int c = 0; c < 3; ++c) {
      const Vec3 q(soup.x[c][0], soup.y[c][0], soup.z[c][0]);
      lo = glm::min(lo, q), hi = glm::max(hi, q);
    }
    const gears::PackedTriangle box = gears::box_cull_bounds(light, lo, hi);
    Vec3 p(xy(rng), xy(rng), sz(rng));
    if (trial % 3 == 0) p = Vec3(v[0]) + Vec3(0.0f, 0.0f, 1e-3f * sz(rng));
    const gears::ItemBounds own = gears::item_bounds(light, &p.x, &p.y, &p.z, 1);
    const bool by_triangle = gears::may_block(tri, own), by_box = gears::may_block(box, own);
    kept_by_triangle += by_triangle;
    culled_by_box += !by_box;
    if (by_triangle) {
      EXPECT_TRUE(by_box) << "trial " << trial;
    }
  }
  std::printf("box cull: triangles keep %d of 20000 samples, boxes cull %d\n", kept_by_triangle,
              culled_by_box);
  EXPECT_GT(kept_by_triangle, 12000);  // measured 12933
  EXPECT_GT(culled_by_box, 4500);      // measured 5044
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
  const gears::FlatLight light = unit_light();
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

/// The gather (16 cache lines at a time, transposed, where AVX-512 is available; one by one
/// otherwise and for the tail) keeps exactly the list's entries that may_block() keeps, in order,
/// with every field: random cull bounds and lists of 0 … 70 entries, 30 % of them kept.
TEST(Gears, GatherKeepsWhatMayBlockKeepsInOrder) {
  std::mt19937 rng(23);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  std::vector<gears::PackedTriangle> tris(200);
  std::vector<gears::TrianglePlane> planes(200);
  for (size_t t = 0; t < tris.size(); ++t) {
    for (float& x : tris[t].v) x = unit(rng);
    tris[t].zmin = unit(rng);
    tris[t].hx0 = unit(rng), tris[t].hx1 = unit(rng), tris[t].hy0 = unit(rng);
    tris[t].hy1 = unit(rng);
    tris[t].opaque = t % 3 != 0, tris[t].solid = static_cast<uint32_t>(t % 7);
    planes[t].nx = unit(rng), planes[t].lmax = unit(rng);
  }
  const gears::ItemBounds item{2.0f, 0.3f, 0.7f, 0.3f, 0.7f};  // every depth; ≈ 30 % per slab
  gears::CandidateBatch batch;
  size_t kept_total = 0;
  for (int n = 0; n <= 70; ++n) {
    std::vector<gears::CellPair> list(n);
    for (auto& pair : list) pair = {0, static_cast<uint32_t>(unit(rng) * 199.0f)};
    batch.gather(tris.data(), planes.data(), list.data(), list.data() + n, item);
    std::vector<uint32_t> want;
    for (const auto& pair : list)
      if (gears::may_block(tris[pair.item], item)) want.push_back(pair.item);
    ASSERT_EQ(batch.count, static_cast<int>(want.size())) << n;
    EXPECT_EQ(batch.read, n);
    for (size_t i = 0; i < want.size(); ++i) {
      const gears::PackedTriangle& t = tris[want[i]];
      ASSERT_EQ(batch.tri[i], want[i]);
      for (int c = 0; c < 9; ++c) ASSERT_EQ(batch.v[c][i], t.v[c]);
      ASSERT_EQ(batch.zmin[i], t.zmin);
      ASSERT_EQ(batch.hx0[i], t.hx0);
      ASSERT_EQ(batch.hx1[i], t.hx1);
      ASSERT_EQ(batch.hy0[i], t.hy0);
      ASSERT_EQ(batch.hy1[i], t.hy1);
      ASSERT_EQ(batch.opaque[i], t.opaque);
      ASSERT_EQ(batch.solid[i], t.solid);
      ASSERT_EQ(batch.nx[i], planes[want[i]].nx);
      ASSERT_EQ(batch.lmax[i], planes[want[i]].lmax);
    }
    kept_total += want.size();
  }
  EXPECT_GT(kept_total, 100u);
}

/// raster_rows_or rasterizes lanes whose shadow box is a few rows tall row by row (one row of 16
/// triangles at a time) and the others triangle by triangle; both give the bits raster_rows gives
/// each triangle alone. Random batches of small and large triangles seen from random points, k of
/// 5, 16 and 32 (two row registers), including lines parallel to the rows.
TEST(Gears, RowByRowRasterizationEqualsPerTriangleRows) {
  std::mt19937 rng(17);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  int short_batches = 0, lanes_covering = 0, flat_lanes = 0;
  for (int trial = 0; trial < 3000; ++trial) {
    const int k = trial % 3 == 0 ? 5 : trial % 3 == 1 ? 16 : 32;
    const Vec3 p(unit(rng) * 2.0f - 0.5f, unit(rng) * 2.0f - 0.5f, 1.0f + 3.0f * unit(rng));
    // Sizes from a hundredth of the sample spacing (dense meshes) to a tenth of the light.
    const float size = (trial % 4 == 3 ? 0.1f : 0.01f + 0.1f * unit(rng)) * 0.3f;
    std::vector<std::array<Vec3, 3>> tris(gears::kLanes);
    for (auto& tri : tris) {
      const Vec3 x(unit(rng), unit(rng), 0.0f);
      const Vec3 centre = p + (0.2f + 0.6f * unit(rng)) * (x - p);
      for (Vec3& q : tri)
        q = centre + size * Vec3(unit(rng) - 0.5f, unit(rng) - 0.5f, unit(rng) - 0.5f);
    }
    // Edge 0–1 of the first along u: its line is parallel to the rows (b = 0).
    tris[0][1].y = tris[0][0].y, tris[0][1].z = tris[0][0].z;
    const gears::CandidateBatch batch = test::opaque_batch(tris);
    ASSERT_EQ(batch.count, gears::kLanes);
    gears::PixelLight light;
    light.p = p, light.w = -p;
    gears::LineBatch lines;
    const uint32_t lanes =
        gears::setup_batch(batch, 0, light, Vec2(0.5f / k), Vec2(1 - 0.5f / k), k, lines);
    int few = 0;
    for (int l = 0; l < gears::kLanes; ++l) {
      const bool short_box = (lanes >> l & 1) && (lines.cells.boxed >> l & 1) &&
                             lines.cells.box[3][l] - lines.cells.box[2][l] < 4;
      few += short_box;
      bool flat = false;
      for (int m = 0; m < 4; ++m) flat |= lines.b[m][l] == 0.0f;
      flat_lanes += short_box && flat;
    }
    short_batches += few > 4;
    uint32_t want[32] = {}, got[32] = {};
    uint32_t want_hit = 0;
    for (int l = 0; l < gears::kLanes; ++l) {
      if (!(lanes >> l & 1)) continue;
      uint32_t one[48] = {};
      if (gears::raster_rows(lines, l, k, one) != 0) want_hit |= 1u << l;
      for (int j = 0; j < k; ++j) want[j] |= one[j];
    }
    const uint32_t hit = gears::raster_rows_or(lines, lanes, k, got);
    lanes_covering += std::popcount(hit);
    ASSERT_EQ(hit, want_hit) << "trial " << trial;
    for (int j = 0; j < 32; ++j) ASSERT_EQ(got[j], want[j]) << "trial " << trial << " row " << j;
  }
  std::printf(
      "row by row: %d of 3000 batches mostly short, %d lanes cover, %d short with a flat "
      "edge\n",
      short_batches, lanes_covering, flat_lanes);
  EXPECT_GT(short_batches, 800);
  EXPECT_GT(lanes_covering, 3500);
  EXPECT_GT(flat_lanes, 300);
}

/// Bit-for-bit equal per-sample masks of two runs (every pixel, every word).
void expect_same_masks(const MethodResult& a, const MethodResult& b, const std::string& what) {
  const SampleMasks& ma = *a.per_light[0].masks;
  const SampleMasks& mb = *b.per_light[0].masks;
  ASSERT_EQ(ma.width() * ma.height(), mb.width() * mb.height());
  size_t differ = 0;
  for (size_t i = 0; i < size_t(ma.width()) * ma.height(); ++i)
    for (int w = 0; w < ma.words_per_pixel(); ++w) differ += ma.pixel(i)[w] != mb.pixel(i)[w];
  EXPECT_EQ(differ, 0u) << what;
}

Scene glass_spheres(bool semi_opaque);  // below, with the semi-opaque tests

/// The sample groups of a work item (option `group`), the longer items of long cell lists
/// (`long_chunk`), the hidden cull (`hidden_cull`) and the pixels' order (`deepest_first`) change
/// which candidates each pixel's cull scans, sets up and rasterizes, never its masks: a rectangle,
/// a disk and a sphere light (the last is not flat: one group per item), the default scene,
/// semi-opaque spheres (V equal too), and a one-cell grid where every cell list is long and every
/// cell spans the whole depth range (sphere tops and the ground behind them).
TEST(Gears, SampleGroupsDoNotChangeTheMasks) {
  std::vector<std::pair<std::string, TestFrame>> frames;
  frames.emplace_back("spheres", make_test_frame("spheres", 32, 32, grid_samples(8)));
  frames.emplace_back("default", make_test_frame("default", 32, 32, grid_samples(8)));
  for (LightShape shape : {LightShape::disk, LightShape::sphere})
    frames.emplace_back(shape == LightShape::disk ? "disk" : "sphere",
                        make_test_frame(round_light_scene(shape), 32, 32, grid_samples(8)));
  frames.emplace_back("glass", make_test_frame(glass_spheres(true), 32, 32, grid_samples(8)));
  for (auto& [name, t] : frames)
    for (const char* grid : {"16", "1"}) {
      if (name != "spheres" && grid[0] == '1' && grid[1] == 0) continue;
      const MethodResult off =
          t.run("gears", {{"group", "0"}, {"hidden_cull", "false"}, {"grid", grid}}, true);
      for (const auto& opts : std::vector<std::map<std::string, std::string>>{
               {{"grid", grid}},  // defaults: groups of 8, long items of 4 × 32 samples
               {{"grid", grid}, {"hidden_cull", "false"}},
               {{"grid", grid}, {"deepest_first", "false"}},
               {{"grid", grid}, {"group", "3"}, {"long_chunk", "64"}, {"chunk", "5"}}}) {
        const MethodResult on = t.run("gears", opts, true);
        std::string what = name + " grid " + grid;
        for (const auto& [key, value] : opts) what += " " + key + "=" + value;
        expect_same_masks(off, on, what);
        // Semi-opaque occluders: the transmittances too (V, not only the bits).
        EXPECT_EQ(on.per_light[0].lit.pixels(), off.per_light[0].lit.pixels()) << what;
      }
    }
}

/// assign_triangles writes each cell's list at once in cell order (a counting sort by cell over
/// chunks of the depth-ordered triangles): the lists partition the pairs cell by cell, each in
/// strictly increasing (zmin, id) order — what the depth cuts read as prefixes — with every
/// triangle once per cell. 4 000 small random triangles over a cloud of samples, on grids of 8²
/// cells (the 16 chunks' histograms meet in every cell) and 64² cells (fewer chunks).
TEST(Gears, AssignmentWritesCellListsInDepthOrder) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> xy(-1.0f, 2.0f), tz(0.2f, 1.5f), unit(0.0f, 1.0f);
  gears::TriangleSoup soup = small_random_triangles(rng, xy, tz, 4000, 0.05f, 0.2f);
  // A third of them flat at one depth, so ties of zmin are broken by the id.
  for (size_t t = 0; t < soup.size(); t += 3)
    for (int c = 0; c < 3; ++c) soup.z[c][t] = 0.75f;
  std::vector<Vec3> samples(3000);
  std::vector<uint32_t> ids(samples.size());
  for (size_t i = 0; i < samples.size(); ++i)
    samples[i] = Vec3(3.0f * unit(rng) - 1.0f, 3.0f * unit(rng) - 1.0f, 1.6f + unit(rng)),
    ids[i] = static_cast<uint32_t>(i);
  const std::vector<Vec3> corners = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(1, 1, 0)};
  for (const int resolution : {8, 64}) {
    const gears::GridCamera cam =
        gears::make_grid_camera(gears::LightSpace{}, corners, 0.0f, samples, 1.0f, resolution);
    const gears::PixelCells cells = gears::bucket_pixels(cam, ids, samples);
    gears::AssignStats stats;
    const gears::CellTriangles table =
        gears::assign_triangles(cam, soup, +1, cells, gears::AssignOptions{}, stats);
    ASSERT_EQ(table.pairs.size(), stats.pairs);
    ASSERT_GT(stats.pairs, soup.size());  // most triangles reach several cells
    uint32_t at = 0;
    for (int c = 0; c < cam.cell_count(); ++c) {
      ASSERT_EQ(table.begin[c], at) << "cell " << c;
      ASSERT_GE(table.end[c], table.begin[c]);
      for (uint32_t i = table.begin[c]; i < table.end[c]; ++i) {
        ASSERT_EQ(table.pairs[i].cell, static_cast<uint32_t>(c));
        if (i == table.begin[c]) continue;
        const uint32_t s = table.pairs[i - 1].item, t = table.pairs[i].item;
        ASSERT_TRUE(table.zmin[s] < table.zmin[t] || (table.zmin[s] == table.zmin[t] && s < t))
            << "cell " << c << " entries " << i - 1 << ", " << i;
      }
      at = table.end[c];
    }
    EXPECT_EQ(at, table.pairs.size());
  }
}

/// The grid's resolution: an explicit option as it is; 0 one cell per 8 × 8 image pixels of the
/// larger side, at least 16.
TEST(Gears, GridResolutionFollowsTheImage) {
  EXPECT_EQ(gears::grid_resolution(37, 512, 512), 37);
  EXPECT_EQ(gears::grid_resolution(0, 512, 512), 64);
  EXPECT_EQ(gears::grid_resolution(0, 1024, 768), 128);
  EXPECT_EQ(gears::grid_resolution(0, 256, 1000), 125);
  EXPECT_EQ(gears::grid_resolution(0, 64, 64), 16);
  EXPECT_EQ(gears::grid_resolution(0, 1, 1), 16);
}

/// CandidateBatch::narrow with a group's bounds keeps, for every sample of the group, exactly
/// the candidates keep() would keep from the whole item batch, in the same order: random
/// triangles in front of a cluster of 32 samples split into groups of 8 (group_samples), with
/// and without the shadow-box test.
TEST(Gears, GroupCullKeepsWhatEachPixelKeeps) {
  // Second round: every triangle one solid that every sample lies outside of, so the item's and
  // the groups' solid culls (drop_solid_back_faces, narrow) run before the pixels' own.
  for (const bool solids : {false, true}) {
    std::mt19937 rng(3);
    std::uniform_real_distribution<float> xy(-1.5f, 2.5f), tz(0.05f, 2.0f), unit(0.0f, 1.0f);
    gears::FlatLight light;
    light.flat = true, light.lx0 = light.ly0 = 0.0f, light.lx1 = light.ly1 = 1.0f;
    gears::GridCamera cam;
    size_t item_kept = 0, group_kept = 0, pixel_kept = 0, groups = 0, solid_dropped = 0;
    for (int trial = 0; trial < 40; ++trial) {
      const gears::TriangleSoup soup = small_random_triangles(rng, xy, tz, 600, 0.02f, 0.3f);
      std::vector<float> zmin(soup.size());
      for (size_t t = 0; t < soup.size(); ++t)
        zmin[t] = std::min({soup.z[0][t], soup.z[1][t], soup.z[2][t]});
      auto packed = gears::pack_triangles(soup, +1, zmin, light);
      const uint64_t outside = solids ? 1 : 0;
      if (solids)
        for (auto& p : packed) p.solid = 0;
      const auto planes = gears::triangle_planes(soup, gears::plane_test_corners(light, cam));
      // The cell list: every triangle, in (zmin, id) order as assign_triangles writes it.
      std::vector<gears::CellPair> list(soup.size());
      for (size_t t = 0; t < soup.size(); ++t) list[t] = {0, uint32_t(t)};
      std::sort(list.begin(), list.end(), [&](auto a, auto b) {
        return zmin[a.item] < zmin[b.item] || (zmin[a.item] == zmin[b.item] && a.item < b.item);
      });
      const Vec3 centre(xy(rng), xy(rng), 2.0f + 2.0f * unit(rng));
      std::vector<float> px(32), py(32), pz(32);
      for (int i = 0; i < 32; ++i)
        px[i] = centre.x + 1.5f * unit(rng), py[i] = centre.y + 1.5f * unit(rng),
        pz[i] = centre.z + 0.2f * unit(rng);
      gears::CandidateBatch item, group, a, b;
      item.gather(packed.data(), planes.data(), list.data(), list.data() + list.size(),
                  gears::item_bounds(light, px.data(), py.data(), pz.data(), 32));
      gears::CandidateBatch item_solid = item;
      gears::SampleBox box_all{Vec3(kInfinity), Vec3(-kInfinity), outside};
      for (int i = 0; i < 32; ++i) {
        box_all.lo = glm::min(box_all.lo, Vec3(px[i], py[i], pz[i]));
        box_all.hi = glm::max(box_all.hi, Vec3(px[i], py[i], pz[i]));
      }
      item_solid.drop_solid_back_faces(box_all);
      solid_dropped += item.count - item_solid.count;
      item_kept += item.count;
      std::vector<int> order, ends;
      gears::group_samples(light, px.data(), py.data(), pz.data(), 32, 8, order, ends);
      ASSERT_EQ(ends.size(), 4u);
      for (size_t g = 0, g0 = 0; g < ends.size(); g0 = ends[g++]) {
        float gx[8], gy[8], gz[8];
        const int gm = ends[g] - int(g0);
        ASSERT_LE(gm, 8);
        for (int j = 0; j < gm; ++j)
          gx[j] = px[order[g0 + j]], gy[j] = py[order[g0 + j]], gz[j] = pz[order[g0 + j]];
        Vec3 gp[8];
        for (int j = 0; j < gm; ++j) gp[j] = Vec3(gx[j], gy[j], gz[j]);
        group.narrow(item_solid, gears::item_bounds(light, gx, gy, gz, gm), gp, gm, outside);
        group_kept += group.count, ++groups;
        for (int j = 0; j < gm; ++j) {
          const Vec3 p(gx[j], gy[j], gz[j]);
          const gears::ItemBounds own = gears::item_bounds(light, &p.x, &p.y, &p.z, 1);
          const gears::ShadowBoxCull box{Vec2(0.0f), Vec2(1.0f), 16};
          for (const gears::ShadowBoxCull* bc :
               {static_cast<const gears::ShadowBoxCull*>(nullptr), &box}) {
            a.keep(item, 0, item.depth_prefix(own.zmax), own, p, bc, nullptr, outside);
            b.keep(group, 0, group.depth_prefix(own.zmax), own, p, bc, nullptr, outside);
            ASSERT_EQ(a.count, b.count) << "trial " << trial;
            for (int i = 0; i < a.count; ++i) ASSERT_EQ(a.tri[i], b.tri[i]) << "trial " << trial;
            pixel_kept += bc ? 0 : a.count;
          }
        }
      }
    }
    std::printf(
        "solids %d: per item %.0f candidates (%.0f dropped as back faces), per group %.0f, "
        "per pixel %.0f\n",
        int(solids), double(item_kept) / 40, double(solid_dropped) / 40,
        double(group_kept) / groups, double(pixel_kept) / (40 * 32));
    // The groups must cull: measured 106 → 73 → 53 per item, group, pixel (and with the solid
    // cull, 42 of the 106 dropped as back faces for the whole item, then 38 per group, 25 per
    // pixel).
    EXPECT_LT(double(group_kept) / groups, 0.8 * double(item_kept) / 40);
    if (solids) {
      EXPECT_GT(solid_dropped, 0u);
    }
  }
}

/// group_samples: a permutation into groups of at most the size asked for, compact in the slab
/// coordinates; one group in the given order when the light is not flat or a sample is on the
/// light plane.
TEST(Gears, SampleGroupsAreCompactInSlabCoordinates) {
  std::mt19937 rng(9);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  const gears::FlatLight light = unit_light();
  std::vector<float> x(100), y(100), z(100);
  for (int i = 0; i < 100; ++i) x[i] = unit(rng), y[i] = unit(rng), z[i] = 1.0f + 0.1f * unit(rng);
  std::vector<int> order, ends;
  gears::group_samples(light, x.data(), y.data(), z.data(), 100, 8, order, ends);
  std::vector<int> sorted = order;
  std::sort(sorted.begin(), sorted.end());
  for (int i = 0; i < 100; ++i) ASSERT_EQ(sorted[i], i);
  ASSERT_EQ(ends.back(), 100);
  double area = 0.0;
  for (size_t g = 0, g0 = 0; g < ends.size(); g0 = ends[g++]) {
    ASSERT_LE(ends[g] - int(g0), 8);
    ASSERT_GT(ends[g], int(g0));
    float lo[2] = {1e9f, 1e9f}, hi[2] = {-1e9f, -1e9f};
    for (size_t j = g0; j < size_t(ends[g]); ++j) {
      const int i = order[j];
      const float k[2] = {x[i] / z[i], y[i] / z[i]};
      for (int a = 0; a < 2; ++a) lo[a] = std::min(lo[a], k[a]), hi[a] = std::max(hi[a], k[a]);
    }
    area += (hi[0] - lo[0]) * (hi[1] - lo[1]);
  }
  // 16 groups of a k-d split of 100 uniform points: their boxes cover about one unit square in
  // all (measured 0.53); groups in input order would each span nearly the whole square (≈ 16).
  std::printf("groups %zu, total box area %.3f\n", ends.size(), area);
  EXPECT_EQ(ends.size(), 16u);
  EXPECT_LT(area, 1.0);
  gears::FlatLight round;  // not flat: one group
  gears::group_samples(round, x.data(), y.data(), z.data(), 100, 8, order, ends);
  EXPECT_EQ(ends, std::vector<int>{100});
  z[7] = 0.0f;  // a sample on the light plane: no slabs
  gears::group_samples(light, x.data(), y.data(), z.data(), 100, 8, order, ends);
  EXPECT_EQ(ends, std::vector<int>{100});
  EXPECT_EQ(order[7], 7);
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

/// A frame not asked for its masks shades each pixel from its own bits in its work item (no
/// frame-size array): the same V, bit for bit, as shading from the frame's masks, and less memory
/// (at least the array: 64² pixels × 4 words).
TEST(Gears, ShadingWithoutTheFrameMasksGivesTheSameV) {
  for (const char* scene : {"spheres", "quad"}) {
    const auto t = make_test_frame(scene, 64, 64, grid_samples(16));
    const Visibility in_place = t.run("gears", {}, false).per_light[0];
    const Visibility from_masks = t.run("gears", {}, true).per_light[0];
    EXPECT_EQ(in_place.lit.pixels(), from_masks.lit.pixels()) << scene;
    EXPECT_GE(from_masks.counters.at("memory_bytes") - in_place.counters.at("memory_bytes"),
              64.0 * 64.0 * 4.0 * 8.0)
        << scene;
    size_t shadowed = 0;
    for (float v : in_place.lit.pixels()) shadowed += v < 1.0f;
    EXPECT_GT(shadowed, 100u) << scene;
  }
}

/// Semi-opaque occluders need per-sample transmittances only while their pixel is rasterized:
/// the memory they add is one n-float buffer per thread, not frame × samples (here that would be
/// ≈ 3.5 MB: ~3 500 active pixels × 256 samples × 4 bytes).
TEST(Gears, SemiOpaqueMemoryIsPerWorkItem) {
  const auto glass = make_test_frame(glass_spheres(true), 64, 64, grid_samples(16));
  const auto opaque = make_test_frame(glass_spheres(false), 64, 64, grid_samples(16));
  // Both keep their masks (an opaque frame that is not asked for them needs no frame-size array).
  const double with = glass.run("gears", {}, true).per_light[0].counters.at("memory_bytes");
  const double without = opaque.run("gears", {}, true).per_light[0].counters.at("memory_bytes");
  const double per_thread = 256.0 * sizeof(float);
  std::printf("memory: semi-opaque %.0f bytes, opaque %.0f bytes\n", with, without);
  EXPECT_GE(with - without, per_thread);
  EXPECT_LE(with - without, 64 * per_thread);  // at most 64 threads' buffers
}

TEST(Gears, DiskAndSphereLightsMatchRaytrace) {
  for (LightShape shape : {LightShape::disk, LightShape::sphere})
    expect_equal_masks(
        compare_masks(make_test_frame(round_light_scene(shape), 48, 48, grid_samples(8))));
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
  // Per-pixel V (opaque bits and the glass sphere's transmittance) as raytrace's, except where a
  // sample's segment grazes a triangle's edge within float tolerance (either answer is right
  // there; which one each side gives depends on FMA and evaluation order: measured, one pixel of
  // 4 096 with or without FMA, the two answers a glass layer apart).
  const MethodResult rt = t.run("raytrace"), ge = t.run("gears");
  const GBuffer& g = t.frame->gbuffer();
  std::vector<Vec2> uv(t.frame->samples().count());
  double max_dv = 0.0;
  int differ = 0, unexplained = 0;
  for (size_t i = 0; i < rt.per_light[0].lit.size(); ++i) {
    const double dv = std::abs(rt.per_light[0].lit[i] - ge.per_light[0].lit[i]);
    if (dv <= 1e-5) continue;
    ++differ;
    max_dv = std::max(max_dv, dv);
    t.frame->samples().pixel_samples(static_cast<int>(i % g.width), static_cast<int>(i / g.width),
                                     uv);
    const Vec3 o = g.shadow_origin(i);
    bool tie = false;
    for (const Vec2& q : uv)
      tie =
          tie || ambiguous(*t.scene, DVec3(o), DVec3(light_frame(t.scene->lights[0], o).point(q)));
    unexplained += !tie;
  }
  std::printf("sphere light in a room: %d pixels differ (max |dV| %.2e), %d unexplained\n", differ,
              max_dv, unexplained);
  EXPECT_LE(differ, 2);
  EXPECT_EQ(unexplained, 0);
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
  // The paper's Table 2 steps are each reported by name (`get` reads 0 for a stage never added,
  // so presence is what a missing stage would fail), each with a duration.
  const auto& stages = v.times.stages();
  for (const char* stage : {"project_pixels", "count_prefix_sum", "write_pairs", "sort_pairs",
                            "bitmask_rasterization", "shading"}) {
    const auto it = std::find_if(stages.begin(), stages.end(),
                                 [&](const auto& entry) { return entry.first == stage; });
    ASSERT_NE(it, stages.end()) << stage;
    EXPECT_TRUE(std::isfinite(it->second) && it->second >= 0.0) << stage << ": " << it->second;
  }
  EXPECT_GT(v.times.total(), 0.0);
}

// The item batch is in depth order, so each pixel's depth cut is a prefix of it and the per-pixel
// cull scans only that: fewer candidates than the item kept (a full scan would read them all),
// never fewer than it sets up.
TEST(Gears, PerPixelCullScansOnlyTheDepthPrefix) {
  const auto t = make_test_frame("spheres", 64, 64, grid_samples(16));
  const Visibility v = t.run("gears", {{"group", "0"}}).per_light[0];
  const double item = v.counters.at("assignments_item");
  const double scanned = v.counters.at("pixel_cull_reads");
  std::printf("item candidates %.0f, scanned per pixel %.0f (%.3f), set up %.0f\n", item, scanned,
              scanned / item, v.counters.at("assignments_total"));
  EXPECT_LE(scanned, 0.87 * item);  // measured 0.816 (the prefix, less the umbrae's early exits)
  EXPECT_GE(scanned, v.counters.at("assignments_total"));
}

/// Deepest candidates first (`deepest_first`): a pixel's nearest layer fills an umbra early and
/// hides what lies behind it, so the per-pixel culls scan and set up less, with the same masks
/// (64², k 16: the closed spheres, and the default scene with its alpha-tested fence).
TEST(Gears, DeepestFirstScansAndSetsUpLess) {
  struct Case {
    const char* scene;
    double scan_bound, setup_bound;  // deepest first / list order
  };
  // Measured 0.974, 0.674 and 0.971, 1.000 (the default grid, 16 cells at 64²; 0.962, 0.737 and
  // 0.940, 1.001 with 128): the fence is one layer, so there only the umbrae's early exits move.
  for (const Case& c : {Case{"spheres", 0.985, 0.72}, Case{"default", 0.985, 1.01}}) {
    const auto t = make_test_frame(c.scene, 64, 64, grid_samples(16));
    const MethodResult first = t.run("gears", {}, true);
    const MethodResult list = t.run("gears", {{"deepest_first", "false"}}, true);
    expect_same_masks(list, first, c.scene);
    const auto& on = first.per_light[0].counters;
    const auto& off = list.per_light[0].counters;
    const double scan = on.at("pixel_cull_reads") / off.at("pixel_cull_reads");
    const double setup = on.at("assignments_total") / off.at("assignments_total");
    std::printf("%s: deepest first / list order: scanned %.3f, set up %.3f\n", c.scene, scan,
                setup);
    EXPECT_LT(scan, c.scan_bound) << c.scene;
    EXPECT_LT(setup, c.setup_bound) << c.scene;
  }
}

/// The mesh-box cull leaves most of the ground out of the grid on `spheres` (64², k 16) and sets
/// up the same candidates: a pixel no mesh box can shadow sets up no triangle.
TEST(Gears, BoxCullLeavesOutPixelsNothingCanShadow) {
  const auto t = make_test_frame("spheres", 64, 64, grid_samples(16));
  const Visibility on = t.run("gears").per_light[0];
  const Visibility off = t.run("gears", {{"box_cull", "false"}}).per_light[0];
  const double culled = on.counters.at("pixels_box_culled");
  const double active = on.counters.at("active_pixels");
  std::printf("box cull: %.0f of %.0f active pixels (%.3f)\n", culled, active, culled / active);
  EXPECT_GT(culled, 0.38 * active);  // measured 0.407
  EXPECT_EQ(off.counters.at("pixels_box_culled"), 0.0);
  EXPECT_NEAR(on.counters.at("assignments_total"), off.counters.at("assignments_total"),
              1e-3 * off.counters.at("assignments_total"));
  EXPECT_LE(on.counters.at("gather_reads"), off.counters.at("gather_reads"));
}

/// The groups' own cull cuts what the per-pixel culls scan on a frame to under a third (spheres
/// 64², k 16, grid 16 so that cells hold dozens of samples; measured 0.29), and sets up the same
/// candidates up to the early exits' chunking.
TEST(Gears, SampleGroupsCutThePerPixelScan) {
  const auto t = make_test_frame("spheres", 64, 64, grid_samples(16));
  const Visibility off =
      t.run("gears", {{"group", "0"}, {"grid", "16"}, {"hidden_cull", "false"}}).per_light[0];
  const Visibility on = t.run("gears", {{"grid", "16"}, {"hidden_cull", "false"}}).per_light[0];
  const double ratio = on.counters.at("pixel_cull_reads") / off.counters.at("pixel_cull_reads");
  std::printf("per-pixel scan with groups / without: %.3f; group candidates %.0f of %.0f\n", ratio,
              on.counters.at("assignments_group"), on.counters.at("assignments_item"));
  EXPECT_LT(ratio, 0.35);  // measured 0.290
  EXPECT_LT(on.counters.at("assignments_group"), on.counters.at("assignments_item"));
  EXPECT_EQ(off.counters.at("assignments_group"), off.counters.at("assignments_item"));
  // Only the early exits move (the chunks end at each batch's own depth prefix): 1.3e-3 measured.
  EXPECT_NEAR(on.counters.at("assignments_in_volume"), off.counters.at("assignments_in_volume"),
              2e-3 * off.counters.at("assignments_in_volume"));
}

}  // namespace
}  // namespace penumbra
