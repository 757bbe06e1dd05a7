// Light-space depth maps: a perspective depth render of the scene's casters from one light point
// [Forest 2008 §2.2.2; Valient 2005 §1], with front-face, back-face or both-face variants
// (the soft shadow maps of Atty et al. need separate front- and back-face occluder maps).
#pragma once

#include <span>

#include "penumbra/core/image.hpp"
#include "penumbra/raster/projection.hpp"
#include "penumbra/scene/scene.hpp"

namespace penumbra {

/// Which caster faces enter the map, judged from the light point: front = the side the triangle's
/// normal cross(p1−p0, p2−p0) points to faces the light.
enum class FaceSelect { front, back, both };

struct DepthMapSpec {
  int resolution = 1024;  // square map, resolution² texels
  FaceSelect faces = FaceSelect::front;
};

struct DepthMap {
  Projection proj;     // from the light point; square, texel (i, j) centre at (i + 0.5, j + 0.5)
  Image<float> depth;  // view depth along proj.forward of the nearest selected caster; +inf: none
  double texel_tan = 0.0;       // one texel's width in tangent units (2·tan_half / resolution)
  float min_depth = kInfinity;  // nearest depth stored anywhere (PCSS's blocker-search bound)

  int resolution() const { return depth.width(); }
  /// Light-space position of a world point: map coordinates (texels) and view depth. False when
  /// the point is not in front of the light.
  bool project(const DVec3& world, double& sx, double& sy, double& view_depth) const {
    const DVec4 c = proj.to_clip(DVec4(world, 1.0));
    if (!(c.w > 0.0)) return false;
    const DVec3 s = proj.to_screen(c);
    sx = s.x;
    sy = s.y;
    view_depth = c.w;
    return true;
  }
  /// Stored depth at a texel; +inf (nothing) outside the map.
  float at(int x, int y) const {
    if (x < 0 || y < 0 || x >= depth.width() || y >= depth.height()) return kInfinity;
    return depth(x, y);
  }
};

/// The frustum of a depth map: from `light_point` toward the centre of `cover` (a set of world
/// points, e.g. the receivers), the narrowest square one containing them all (tangent half-angle
/// capped at tan 85°; points beyond fall outside the map); near plane at 10⁻⁶ scene diagonals.
struct DepthMapView {
  Projection proj;
  double texel_tan = 0.0;
  double near = 0.0;
};
DepthMapView fit_depth_map_view(const Scene& scene, const Vec3& light_point,
                                std::span<const Vec3> cover, int resolution);

/// Renders the depth map of every mesh with casts_shadows from `light_point` in the frustum of
/// fit_depth_map_view. Alpha textures and transmittance are ignored: every caster triangle is
/// opaque. Tile-parallel (bands of rows, each texel written by one task): deterministic.
DepthMap render_depth_map(const Scene& scene, const Vec3& light_point, std::span<const Vec3> cover,
                          const DepthMapSpec& spec);

}  // namespace penumbra
