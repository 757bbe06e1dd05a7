// The G-buffer: per pixel, the first surface hit by one primary ray through the pixel centre.
#pragma once

#include <algorithm>
#include <cstdint>

#include "penumbra/core/image.hpp"
#include "penumbra/core/math.hpp"

namespace penumbra {

class EmbreeScene;
struct Camera;

struct GBuffer {
  int width = 0;
  int height = 0;
  Image<Vec3> world_pos;       // hit point, world space
  Image<Vec3> geo_normal;      // unit geometric normal, flipped to face the camera
  Image<Vec3> shading_normal;  // interpolated vertex normal (or geo_normal), facing the camera
  Image<float> depth;      // distance from the camera along the ray, world units; +inf = background
  Image<int32_t> mesh_id;  // index into Scene::meshes; -1 = background
  Image<int32_t> prim_id;  // triangle index within the mesh
  Image<Vec2> uv;          // texture coordinates at the hit (0 without UVs)
  Image<float> ray_offset;  // self-intersection offset (world units) of the shared policy below

  size_t pixel_count() const { return static_cast<size_t>(width) * height; }
  bool is_background(size_t i) const { return mesh_id[i] < 0; }

  /// The one self-intersection policy every method shares: shadow rays, projections and
  /// shadow-volume tests all start at the hit point moved `ray_offset[i]` along the
  /// camera-facing geometric normal. The offset is relative to the hit triangle, as robust ray
  /// tracers make it (the rounding of a reconstructed hit point and of a ray-triangle test grows
  /// with the coordinates' magnitude): kRayOffsetRelative × the largest |coordinate| of the hit
  /// triangle's vertices, which bounds both the point's magnitude and the triangle's extent (its
  /// local feature size). It does not depend on anything else in the scene — a distant object
  /// leaves every pixel's origin unchanged — and scales with the scene, so a scene rendered at
  /// 1e-7 or 1e9 times its size gives the same image.
  Vec3 shadow_origin(size_t i) const { return world_pos[i] + ray_offset[i] * geo_normal[i]; }
};

/// About 800 float ulps of the triangle's coordinates: far above the few ulps of error of the
/// barycentric hit point and Embree's watertight test, far below a pixel's footprint. (1e-5 was
/// tried: exact and raytrace agree there too, but the float wedge projections of edges a few ulps
/// from the shading point speckle the wedge methods' self-shadowing — bunny 0.044 vs 0.039.)
inline constexpr float kRayOffsetRelative = 1e-4f;

/// The shared offset for a hit on triangle (p0, p1, p2).
inline float ray_offset_for_triangle(const Vec3& p0, const Vec3& p1, const Vec3& p2) {
  const Vec3 m = glm::max(glm::max(glm::abs(p0), glm::abs(p1)), glm::abs(p2));
  return kRayOffsetRelative * std::max({m.x, m.y, m.z});
}

/// A width × height G-buffer at its background values (no hit: depth +inf, ids −1, the rest 0).
/// Most of its cost is the first touch of its pages (64 bytes a pixel), which needs no scene:
/// `render` allocates it while the scene loads.
GBuffer background_gbuffer(int width, int height);

/// Traces one primary ray per pixel with Embree (all cores), into `layers` when they are a
/// background_gbuffer of the camera's size (a new one otherwise). Pixels no ray hits keep their
/// background values.
GBuffer render_gbuffer(const EmbreeScene& embree, const Camera& camera, GBuffer layers = {});

}  // namespace penumbra
