// The G-buffer: per pixel, the first surface hit by one primary ray through the pixel centre.
#pragma once

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
  /// Self-intersection offset (world units) of the shared policy below.
  float ray_offset = 0.0f;

  size_t pixel_count() const { return static_cast<size_t>(width) * height; }
  bool is_background(size_t i) const { return mesh_id[i] < 0; }

  /// The one self-intersection policy every method shares: shadow rays, projections and
  /// shadow-volume tests all start at the hit point moved `ray_offset` along the camera-facing
  /// geometric normal. ray_offset = 1e-4 × the scene's bounding-box diagonal (set by
  /// render_gbuffer): large enough that float rounding on the hit point never re-hits the
  /// receiver, small enough to be invisible at any screen resolution we render.
  Vec3 shadow_origin(size_t i) const { return world_pos[i] + ray_offset * geo_normal[i]; }
};

inline constexpr float kRayOffsetPerDiagonal = 1e-4f;

/// Traces one primary ray per pixel with Embree (all cores).
GBuffer render_gbuffer(const EmbreeScene& embree, const Camera& camera);

}  // namespace penumbra
