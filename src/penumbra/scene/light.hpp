// Area lights (rectangle, disk, sphere, textured rectangle) and the point light as their limit.
#pragma once

#include <string>
#include <string_view>

#include "penumbra/core/math.hpp"

namespace penumbra {

enum class LightShape { point, rect, disk, sphere };

std::string_view to_string(LightShape shape);

struct Light {
  std::string name;
  LightShape shape = LightShape::rect;
  Vec3 center{0.0f, 2.0f, 0.0f};
  /// rect: the two full edge vectors (side lengths are their lengths). The light emits toward
  /// normalize(cross(edge_u, edge_v)) (one-sided unless two_sided).
  Vec3 edge_u{0.5f, 0.0f, 0.0f};
  Vec3 edge_v{0.0f, 0.0f, 0.5f};
  /// disk: the direction it emits toward. sphere: unused.
  Vec3 normal{0.0f, -1.0f, 0.0f};
  float radius = 0.0f;        // disk, sphere
  Vec3 radiance{1.0f};        // emitted radiance, linear RGB
  int emission_texture = -1;  // rect only: radiance is multiplied by this texture over light uv
  bool two_sided = false;

  /// Emitting area in world units² (0 for a point light).
  float area() const;
  bool is_textured() const { return emission_texture >= 0; }
};

/// The parallelogram that bounds the light's emitting shape as seen from one receiver point.
/// Light samples and the exact reference both work in its uv square [0,1]²:
/// world_pos = corner + u * edge_u + v * edge_v. Round shapes (disk, sphere) emit only inside the
/// circle inscribed in the square; the rest of the square is masked (GEARS §5 does the same).
struct LightFrame {
  Vec3 corner{0.0f};
  Vec3 edge_u{0.0f};
  Vec3 edge_v{0.0f};
  Vec3 emit_normal{0.0f, -1.0f, 0.0f};  // unit; points toward the side that receives light
  bool round = false;

  Vec3 point(Vec2 light_uv) const { return corner + light_uv.x * edge_u + light_uv.y * edge_v; }
  Vec3 center() const { return corner + 0.5f * (edge_u + edge_v); }
  /// Does light_uv lie on the emitting shape? (Always for rectangles and points.)
  bool emits(Vec2 light_uv) const;
  /// Emitting area in uv units (1 for a rectangle, pi/4 for a round light).
  float uv_area() const;
};

/// The light's frame as seen from `receiver_world_pos`. Constant for point, rect and disk lights.
/// A sphere light is replaced by its silhouette disk from the receiver: centre moved r²/d toward
/// the receiver, radius r·sqrt(1 − r²/d²) — the same solid angle as the visible cap. A receiver
/// inside the sphere (d ≤ r, "light touching geometry") gets the disk through the centre.
LightFrame light_frame(const Light& light, const Vec3& receiver_world_pos);

/// Whether light_frame depends on the receiver (a sphere light's silhouette disk); otherwise the
/// frame from any point, e.g. light_frame(light, light.center), serves every receiver.
inline bool frame_depends_on_receiver(const Light& light) {
  return light.shape == LightShape::sphere;
}

}  // namespace penumbra
