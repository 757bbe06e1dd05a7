#include "penumbra/render/gbuffer.hpp"

#include <tbb/parallel_invoke.h>

#include "penumbra/core/error.hpp"
#include "penumbra/core/parallel.hpp"
#include "penumbra/render/embree_scene.hpp"
#include "penumbra/scene/camera.hpp"

namespace penumbra {

GBuffer background_gbuffer(int width, int height) {
  GBuffer g;
  g.width = width;
  g.height = height;
  // 64 bytes a pixel, first touched here (page faults and the fill: ≈ 15 ms serial at 1024²), so
  // the eight layers are allocated side by side.
  tbb::parallel_invoke([&] { g.world_pos = Image<Vec3>(width, height, Vec3(0.0f)); },
                       [&] { g.geo_normal = Image<Vec3>(width, height, Vec3(0.0f)); },
                       [&] { g.shading_normal = Image<Vec3>(width, height, Vec3(0.0f)); },
                       [&] { g.depth = Image<float>(width, height, kInfinity); },
                       [&] { g.mesh_id = Image<int32_t>(width, height, -1); },
                       [&] { g.prim_id = Image<int32_t>(width, height, -1); },
                       [&] { g.uv = Image<Vec2>(width, height, Vec2(0.0f)); },
                       [&] { g.ray_offset = Image<float>(width, height, 0.0f); });
  return g;
}

namespace {

/// Every layer allocated at the camera's size (their values are background_gbuffer's: the caller's
/// promise).
bool has_layers_for(const GBuffer& g, const Camera& camera) {
  const size_t n = static_cast<size_t>(camera.width) * camera.height;
  return g.width == camera.width && g.height == camera.height && g.world_pos.size() == n &&
         g.geo_normal.size() == n && g.shading_normal.size() == n && g.depth.size() == n &&
         g.mesh_id.size() == n && g.prim_id.size() == n && g.uv.size() == n &&
         g.ray_offset.size() == n;
}

}  // namespace

GBuffer render_gbuffer(const EmbreeScene& embree, const Camera& camera, GBuffer layers) {
  const Scene& scene = embree.scene();
  GBuffer g = has_layers_for(layers, camera) ? std::move(layers)
                                             : background_gbuffer(camera.width, camera.height);

  const Camera::RayBasis rays = camera.ray_basis();
  // Primary rays in 4×4 pixel packets (rtcIntersect16): coherent rays share the traversal, about
  // 2× faster than single rays. Row bands of 4 in parallel; each pixel is written by one task.
  constexpr int kTile = 4;
  parallel_rows((g.height + kTile - 1) / kTile, [&](int band) {
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    context.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
    const int y0 = band * kTile;
    for (int x0 = 0; x0 < g.width; x0 += kTile) {
      alignas(64) int valid[16];
      alignas(64) RTCRayHit16 rh;
      for (int l = 0; l < 16; ++l) {
        const int x = x0 + l % kTile, y = y0 + l / kTile;
        valid[l] = x < g.width && y < g.height ? -1 : 0;
        const Vec3 dir =
            valid[l] ? rays.direction(static_cast<float>(x), static_cast<float>(y)) : rays.forward;
        // validate_scene guarantees a finite camera basis; Embree aborts on a non-finite ray.
        if (!is_finite(dir)) throw Error("internal: non-finite camera ray");
        rh.ray.org_x[l] = camera.position.x;
        rh.ray.org_y[l] = camera.position.y;
        rh.ray.org_z[l] = camera.position.z;
        rh.ray.dir_x[l] = dir.x;
        rh.ray.dir_y[l] = dir.y;
        rh.ray.dir_z[l] = dir.z;
        rh.ray.tnear[l] = 0.0f;
        rh.ray.tfar[l] = kInfinity;
        rh.ray.time[l] = 0.0f;
        rh.ray.mask[l] = EmbreeScene::kMaskVisible;
        rh.ray.id[l] = static_cast<unsigned>(l);
        rh.ray.flags[l] = 0;
        rh.hit.geomID[l] = RTC_INVALID_GEOMETRY_ID;
        rh.hit.instID[0][l] = RTC_INVALID_GEOMETRY_ID;
      }
      rtcIntersect16(valid, embree.handle(), &context, &rh);
      // A packet's rays mostly hit a few triangles (bunny at 1024²: ≈ 13 pixels a triangle):
      // each triangle's vertices, normal and offset are looked up and computed once.
      struct HitTriangle {
        unsigned geom = RTC_INVALID_GEOMETRY_ID, prim = 0;
        int mesh_index = -1;
        Vec3 p0{0.0f}, p1{0.0f}, p2{0.0f}, normal{0.0f};
        float ray_offset = 0.0f;
      } last;
      for (int l = 0; l < 16; ++l) {
        if (!valid[l] || rh.hit.geomID[l] == RTC_INVALID_GEOMETRY_ID) continue;
        const int x = x0 + l % kTile, y = y0 + l / kTile;
        const Vec3 dir(rh.ray.dir_x[l], rh.ray.dir_y[l], rh.ray.dir_z[l]);
        const unsigned prim = rh.hit.primID[l];
        if (rh.hit.geomID[l] != last.geom || prim != last.prim) {
          last.geom = rh.hit.geomID[l];
          last.prim = prim;
          last.mesh_index = embree.mesh_of_geometry(last.geom);
          const Mesh& mesh = scene.meshes[last.mesh_index];
          const Triangle& tri = mesh.triangles[prim];
          last.p0 = mesh.positions[tri.v[0]];
          last.p1 = mesh.positions[tri.v[1]];
          last.p2 = mesh.positions[tri.v[2]];
          last.normal = triangle_normal(last.p0, last.p1, last.p2);
          last.ray_offset = ray_offset_for_triangle(last.p0, last.p1, last.p2);
        }
        const int mesh_index = last.mesh_index;
        const Mesh& mesh = scene.meshes[mesh_index];
        const Triangle& tri = mesh.triangles[prim];
        const Vec3 &p0 = last.p0, &p1 = last.p1, &p2 = last.p2;
        const float u = rh.hit.u[l], v = rh.hit.v[l];
        // Barycentric reconstruction on the triangle, not org + t·dir: the point then lies on the
        // triangle's plane to float precision, which the shared offset policy relies on.
        const Vec3 world_pos = (1.0f - u - v) * p0 + u * p1 + v * p2;
        Vec3 n = last.normal;
        const bool flip = glm::dot(n, dir) > 0.0f;
        if (flip) n = -n;
        Vec3 ns = n;
        if (!mesh.normals.empty()) {
          const Vec3 interp = (1.0f - u - v) * mesh.normals[tri.v[0]] + u * mesh.normals[tri.v[1]] +
                              v * mesh.normals[tri.v[2]];
          const float len = glm::length(interp);
          if (len > 0.0f) ns = (flip ? -interp : interp) / len;
        }
        const size_t i = static_cast<size_t>(y) * g.width + x;
        g.world_pos[i] = world_pos;
        g.geo_normal[i] = n;
        g.shading_normal[i] = ns;
        g.ray_offset[i] = last.ray_offset;
        g.depth[i] = rh.ray.tfar[l];
        g.mesh_id[i] = mesh_index;
        g.prim_id[i] = static_cast<int32_t>(prim);
        g.uv[i] = mesh.uv_at(prim, u, v);
      }
    }
  });
  return g;
}

}  // namespace penumbra
