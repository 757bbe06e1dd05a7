#include "penumbra/raster/depth_map.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

#include "penumbra/core/error.hpp"

namespace penumbra {

namespace {

constexpr int kBand = 32;

struct MapTriangle {
  DVec3 s[3];  // screen (x, y, 1/w), already clipped: may be a fan piece of a clipped triangle
};

}  // namespace

DepthMapView fit_depth_map_view(const Scene& scene, const Vec3& light_point,
                                std::span<const Vec3> cover, int resolution) {
  if (resolution < 1) throw Error("depth map resolution must be positive");
  const DVec3 eye(light_point);
  // Frustum: axis toward the centre of the cover points' box, half-angle enclosing them all.
  Bounds3 box;
  for (const Vec3& p : cover) box.extend(p);
  if (box.empty()) box = scene.bounds();
  DVec3 axis = DVec3(box.center()) - eye;
  if (glm::length(axis) < 1e-12) axis = DVec3(0, -1, 0);
  axis = glm::normalize(axis);
  const double max_tan = std::tan(85.0 * kPi / 180.0);
  Projection probe = look_projection(eye, axis, 1.0, 1, 1);
  double tan_half = 1e-6;
  for (const Vec3& p : cover) {
    const DVec3 rel = DVec3(p) - eye;
    const double z = glm::dot(rel, probe.forward);
    const double t =
        std::max(std::abs(glm::dot(rel, probe.right)), std::abs(glm::dot(rel, probe.up)));
    tan_half = (z <= 0.0 || t > max_tan * z) ? max_tan : std::max(tan_half, t / z);
  }
  tan_half = std::min(max_tan, tan_half * (1.0 + 1e-3));
  DepthMapView view;
  view.proj = look_projection(eye, axis, tan_half, resolution, resolution);
  view.texel_tan = 2.0 * tan_half / resolution;
  view.near = 1e-6 * std::max(1e-3f, scene.bounds().diagonal());
  return view;
}

DepthMap render_depth_map(const Scene& scene, const Vec3& light_point, std::span<const Vec3> cover,
                          const DepthMapSpec& spec) {
  const DepthMapView view = fit_depth_map_view(scene, light_point, cover, spec.resolution);
  const DVec3 eye(light_point);
  DepthMap map;
  map.proj = view.proj;
  map.depth = Image<float>(spec.resolution, spec.resolution, kInfinity);
  map.texel_tan = view.texel_tan;
  const double near = view.near;

  // Project, cull by face selection, clip; fan-split into screen triangles.
  std::vector<MapTriangle> tris;
  for (const Mesh& mesh : scene.meshes) {
    if (!mesh.casts_shadows) continue;
    for (size_t t = 0; t < mesh.triangle_count(); ++t) {
      const DVec3 p0(mesh.vertex(t, 0)), p1(mesh.vertex(t, 1)), p2(mesh.vertex(t, 2));
      const double side = glm::dot(glm::cross(p1 - p0, p2 - p0), eye - p0);
      if (side == 0.0) continue;
      if (spec.faces == FaceSelect::front && side < 0.0) continue;
      if (spec.faces == FaceSelect::back && side > 0.0) continue;
      const DVec4 world[3] = {DVec4(p0, 1.0), DVec4(p1, 1.0), DVec4(p2, 1.0)};
      const ScreenPolygon poly = project_polygon(map.proj, world, 3, near);
      if (poly.empty() || poly.xmax < 0 || poly.ymax < 0 || poly.xmin > spec.resolution ||
          poly.ymin > spec.resolution)
        continue;
      for (int k = 1; k + 1 < poly.count; ++k)
        tris.push_back({{poly.v[0], poly.v[k], poly.v[k + 1]}});
    }
  }
  // Bin by bands of rows, then rasterize each band in parallel (min depth: order-independent).
  const int bands = (spec.resolution + kBand - 1) / kBand;
  std::vector<std::vector<uint32_t>> bins(bands);
  for (uint32_t i = 0; i < tris.size(); ++i) {
    const MapTriangle& t = tris[i];
    const double ymin = std::min({t.s[0].y, t.s[1].y, t.s[2].y}),
                 ymax = std::max({t.s[0].y, t.s[1].y, t.s[2].y});
    const int b0 = std::clamp(static_cast<int>(std::floor((ymin - 0.5) / kBand)), 0, bands - 1);
    const int b1 = std::clamp(static_cast<int>(std::floor((ymax + 0.5) / kBand)), 0, bands - 1);
    for (int b = b0; b <= b1; ++b) bins[b].push_back(i);
  }
  parallel_bands(spec.resolution, kBand, [&](int first, int last) {
    for (uint32_t i : bins[first / kBand]) {
      const MapTriangle& t = tris[i];
      rasterize_triangle(
          t.s[0], t.s[1], t.s[2], spec.resolution, first, last, [&](int x, int y, double inv_w) {
            const float d = inv_w > 0.0 ? static_cast<float>(1.0 / inv_w) : kInfinity;
            float& texel = map.depth(x, y);
            texel = std::min(texel, d);
          });
    }
  });
  for (float d : map.depth.pixels()) map.min_depth = std::min(map.min_depth, d);
  return map;
}

}  // namespace penumbra
