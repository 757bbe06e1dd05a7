// Software rasterization: projection, homogeneous clipping with points at infinity, watertight
// scan conversion, light-space depth maps (deterministic across thread counts).
#include <gtest/gtest.h>
#include <tbb/task_arena.h>

#include <cmath>
#include <vector>

#include "penumbra/raster/depth_map.hpp"
#include "penumbra/raster/projection.hpp"
#include "penumbra/scene/builtin_scenes.hpp"
#include "penumbra/scene/shapes.hpp"

namespace penumbra {
namespace {

Camera test_camera() {
  Camera c;
  c.position = Vec3(0.5f, 2.0f, 3.0f);
  c.target = Vec3(0.0f, 0.3f, 0.0f);
  c.vfov_deg = 50.0f;
  c.width = 80;
  c.height = 60;
  return c;
}

TEST(Raster, CameraProjectionMatchesPrimaryRays) {
  const Camera cam = test_camera();
  const Projection proj = camera_projection(cam);
  for (int y : {0, 17, 59})
    for (int x : {0, 40, 79}) {
      const Vec3 d = cam.ray_direction(static_cast<float>(x), static_cast<float>(y));
      const DVec3 p = DVec3(cam.position) + 2.5 * DVec3(d);
      const DVec3 s = proj.to_screen(proj.to_clip(DVec4(p, 1.0)));
      EXPECT_NEAR(s.x, x + 0.5, 1e-4);
      EXPECT_NEAR(s.y, y + 0.5, 1e-4);
      // A point at infinity in the same direction projects to the same pixel.
      const DVec3 v = proj.to_screen(proj.to_clip(DVec4(DVec3(d), 0.0)));
      EXPECT_NEAR(v.x, x + 0.5, 1e-4);
      EXPECT_NEAR(v.y, y + 0.5, 1e-4);
    }
}

TEST(Raster, ClippingKeepsTheVisiblePartAndPointsAtInfinity) {
  const Camera cam = test_camera();
  const Projection proj = camera_projection(cam);
  // A triangle with one vertex behind the camera, one in front and one at infinity straight ahead.
  const DVec3 eye(cam.position), fwd = proj.forward;
  const DVec4 world[3] = {DVec4(eye - 1.0 * fwd + 0.3 * proj.right, 1.0),
                          DVec4(eye + 2.0 * fwd, 1.0), DVec4(fwd, 0.0)};
  DVec4 clip[3], out[kMaxClipVertices];
  for (int i = 0; i < 3; ++i) clip[i] = proj.to_clip(world[i]);
  const double near = 0.01;
  const int n = clip_polygon(clip, 3, near, 1.5, out);
  ASSERT_GE(n, 3);
  for (int i = 0; i < n; ++i) {
    EXPECT_GE(out[i].w - near * out[i].z, -1e-12);
    EXPECT_GT(out[i].w, 0.0);
  }
  const ScreenPolygon poly = project_polygon(proj, world, 3, near, 1.5);
  ASSERT_FALSE(poly.empty());
  // The vanishing point of the forward direction is the screen centre; it is inside.
  EXPECT_LE(poly.xmin, 40.0);
  EXPECT_GE(poly.xmax, 40.0);
  double x0 = 0, x1 = 0;
  EXPECT_TRUE(polygon_row_span(poly, 29.5, 30.5, x0, x1));
  EXPECT_LE(x0, 40.0 + 1e-9);
  // Entirely behind the camera: nothing.
  const DVec4 behind[3] = {DVec4(eye - fwd, 1.0), DVec4(eye - 2.0 * fwd + proj.up, 1.0),
                           DVec4(-fwd, 0.0)};
  EXPECT_TRUE(project_polygon(proj, behind, 3, near).empty());
}

TEST(Raster, TriangleFanCoversEveryPixelExactlyOnce) {
  // 17 triangles fanning around an off-grid centre, closing a convex polygon that also has
  // vertices exactly on pixel centres: each covered pixel must be hit once, the polygon's interior
  // pixels all hit.
  const int w = 64, h = 64;
  std::vector<int> hits(w * h, 0);
  const DVec3 centre(31.5, 30.5, 1.0);  // a pixel centre: many edges pass through it
  const int n = 17;
  std::vector<DVec3> ring;
  for (int k = 0; k < n; ++k) {
    const double a = 2.0 * kPi * k / n;
    ring.push_back(DVec3(std::round(centre.x + 25.0 * std::cos(a)) + 0.5,
                         std::round(centre.y + 25.0 * std::sin(a)) + 0.5, 1.0));
  }
  int facing_sum = 0;
  for (int k = 0; k < n; ++k)
    facing_sum += rasterize_triangle(centre, ring[k], ring[(k + 1) % n], w, 0, h,
                                     [&](int x, int y, double inv_w) {
                                       EXPECT_NEAR(inv_w, 1.0, 1e-12);
                                       ++hits[y * w + x];
                                     });
  EXPECT_EQ(std::abs(facing_sum), n);  // all the same winding
  int covered = 0;
  for (int v : hits) {
    EXPECT_LE(v, 1);
    covered += v;
  }
  // The centre pixel and its 8 neighbours are well inside.
  for (int dy = -1; dy <= 1; ++dy)
    for (int dx = -1; dx <= 1; ++dx) EXPECT_EQ(hits[(30 + dy) * w + 31 + dx], 1);
  EXPECT_GT(covered, 1500);
}

TEST(Raster, DepthMapOfAQuadHoldsItsDistanceAndRespectsFaceSelection) {
  Scene s;
  s.meshes.push_back(make_quad(Vec3(0, 1.0f, 0), Vec3(0, 0, 1.0f), Vec3(1.0f, 0, 0)));  // faces +y
  s.materials.push_back(Material{});
  const Vec3 light(0.0f, 3.0f, 0.0f);
  const std::vector<Vec3> cover = {Vec3(-1, 0, -1), Vec3(1, 0, 1), Vec3(-1, 0, 1), Vec3(1, 0, -1)};
  DepthMapSpec spec;
  spec.resolution = 64;
  spec.faces = FaceSelect::front;
  const DepthMap front = render_depth_map(s, light, cover, spec);
  // Straight down through the centre: depth 2.
  EXPECT_NEAR(front.depth(32, 32), 2.0f, 1e-4f);
  double sx = 0, sy = 0, z = 0;
  ASSERT_TRUE(front.project(DVec3(0.2, 1.0, -0.3), sx, sy, z));
  EXPECT_NEAR(z, 2.0,
              1e-9);  // the quad is perpendicular to the axis: its view depth is 2 everywhere
  EXPECT_NEAR(front.depth(static_cast<int>(sx), static_cast<int>(sy)), 2.0f, 1e-4f);
  EXPECT_EQ(front.depth(0, 0), kInfinity);  // outside the quad's footprint
  EXPECT_NEAR(front.min_depth, 2.0f, 1e-4f);
  spec.faces = FaceSelect::back;
  EXPECT_EQ(render_depth_map(s, light, cover, spec).min_depth, kInfinity);
  spec.faces = FaceSelect::both;
  EXPECT_NEAR(render_depth_map(s, light, cover, spec).min_depth, 2.0f, 1e-4f);
}

TEST(Raster, DepthMapIsIndependentOfThreadCount) {
  const Scene s = make_builtin_scene("spheres");
  const std::vector<Vec3> cover = {Vec3(-3, 0, -3), Vec3(3, 0, 3), Vec3(-3, 0, 3), Vec3(3, 0, -3)};
  DepthMapSpec spec;
  spec.resolution = 256;
  spec.faces = FaceSelect::both;
  const DepthMap many = render_depth_map(s, s.lights[0].center, cover, spec);
  tbb::task_arena one(1);
  DepthMap single;
  one.execute([&] { single = render_depth_map(s, s.lights[0].center, cover, spec); });
  EXPECT_EQ(many.depth.pixels(), single.depth.pixels());
  EXPECT_LT(many.min_depth, 2.0f);
}

}  // namespace
}  // namespace penumbra
