#include "penumbra/render/gbuffer.hpp"

#include "penumbra/core/error.hpp"
#include "penumbra/core/parallel.hpp"
#include "penumbra/render/embree_scene.hpp"
#include "penumbra/scene/camera.hpp"

namespace penumbra {

GBuffer render_gbuffer(const EmbreeScene& embree, const Camera& camera) {
  const Scene& scene = embree.scene();
  GBuffer g;
  g.width = camera.width;
  g.height = camera.height;
  g.world_pos = Image<Vec3>(g.width, g.height, Vec3(0.0f));
  g.geo_normal = Image<Vec3>(g.width, g.height, Vec3(0.0f));
  g.shading_normal = Image<Vec3>(g.width, g.height, Vec3(0.0f));
  g.depth = Image<float>(g.width, g.height, kInfinity);
  g.mesh_id = Image<int32_t>(g.width, g.height, -1);
  g.prim_id = Image<int32_t>(g.width, g.height, -1);
  g.uv = Image<Vec2>(g.width, g.height, Vec2(0.0f));
  g.ray_offset = Image<float>(g.width, g.height, 0.0f);

  const Camera::RayBasis rays = camera.ray_basis();
  parallel_rows(g.height, [&](int y) {
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    for (int x = 0; x < g.width; ++x) {
      const Vec3 dir = rays.direction(static_cast<float>(x), static_cast<float>(y));
      // validate_scene guarantees a finite camera basis; Embree aborts on a non-finite ray.
      if (!is_finite(dir)) throw Error("internal: non-finite camera ray");
      RTCRayHit rh{};
      rh.ray.org_x = camera.position.x;
      rh.ray.org_y = camera.position.y;
      rh.ray.org_z = camera.position.z;
      rh.ray.dir_x = dir.x;
      rh.ray.dir_y = dir.y;
      rh.ray.dir_z = dir.z;
      rh.ray.tnear = 0.0f;
      rh.ray.tfar = kInfinity;
      rh.ray.mask = EmbreeScene::kMaskVisible;
      rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
      rtcIntersect1(embree.handle(), &context, &rh);
      if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) continue;

      const int mesh_index = embree.mesh_of_geometry(rh.hit.geomID);
      const Mesh& mesh = scene.meshes[mesh_index];
      const Triangle& tri = mesh.triangles[rh.hit.primID];
      const Vec3 p0 = mesh.positions[tri.v[0]], p1 = mesh.positions[tri.v[1]],
                 p2 = mesh.positions[tri.v[2]];
      const float u = rh.hit.u, v = rh.hit.v;
      // Barycentric reconstruction on the triangle, not org + t·dir: the point then lies on the
      // triangle's plane to float precision, which the shared offset policy relies on.
      const Vec3 world_pos = (1.0f - u - v) * p0 + u * p1 + v * p2;
      Vec3 n = triangle_normal(p0, p1, p2);
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
      g.ray_offset[i] = ray_offset_for_triangle(p0, p1, p2);
      g.depth[i] = rh.ray.tfar;
      g.mesh_id[i] = mesh_index;
      g.prim_id[i] = static_cast<int32_t>(rh.hit.primID);
      g.uv[i] = mesh.uv_at(rh.hit.primID, u, v);
    }
  });
  return g;
}

}  // namespace penumbra
