// GEARS grid camera C [Wang 2014 §3.1 step 3.1]: light space (light uv and depth from the light
// plane), the eye behind the light, and the regular grid G over the projected pixel samples.
#pragma once

#include <cstdint>
#include <vector>

#include "penumbra/core/math.hpp"
#include "penumbra/scene/light.hpp"

namespace penumbra::gears {

/// An affine frame in which the light is simple: world = origin + x·axis_u + y·axis_v + z·axis_n.
/// For a rectangle or disk the light is the unit square [0,1]² at z = 0 (axis_u, axis_v = the
/// LightFrame edges); a point light is the origin; a sphere is the cube [0,1]² × [−r, r] around its
/// centre plane (r in z units). Depth z grows away from the light on the side being computed
/// (`side` = −1 flips it), so every sample of one pass has z ≥ 0 [Wang 2014 §3.1: "the light is
/// single sided and only casts rays in one of the half spaces"].
/// |axis_n| (and a point light's |axis_u|, |axis_v|) is the power of two nearest to the light's
/// size (a point light: its distance to the receivers), so every light-space coordinate is of
/// order 1 at any scene scale and the assignment's and culls' float margins stay relative; a power
/// of two rescales without rounding (with z in world units, a scene scaled by 1e-6 or 1e6 lost
/// blockers: up to 4 % of the samples differed from raytrace).
struct LightSpace {
  Vec3 origin{0.0f};
  Vec3 axis_u{1, 0, 0}, axis_v{0, 1, 0}, axis_n{0, 0, 1};
  // Rows of the inverse of [axis_u axis_v axis_n].
  Vec3 inv_u{1, 0, 0}, inv_v{0, 1, 0}, inv_n{0, 0, 1};

  /// Light-space coordinates of a world point (double arithmetic, rounded once).
  Vec3 to_light(const Vec3& world) const;
  Vec3 to_world(const Vec3& light) const {
    return origin + light.x * axis_u + light.y * axis_v + light.z * axis_n;
  }
};

/// Light space for frame `frame` (rectangle, disk) or, for point and sphere lights, for a plane
/// facing `toward` (a world direction away from the light, e.g. toward the samples).
LightSpace make_light_space(const Light& light, const LightFrame& frame, const Vec3& toward,
                            int side);

/// The grid camera C. Projection of a light-space point q (q.z > eye.z) onto the grid plane:
///   g = eye.xy + (q.xy − eye.xy) · (plane_z − eye.z) / (q.z − eye.z), then to cell units.
/// The image plane is parallel to the light and its axes run along the light edges [Wang 2014
/// §3.1].
struct GridCamera {
  Vec3 eye{0.0f};                   // light space, behind the light (eye.z < every light point's z)
  float plane_z = 1.0f;             // depth of the image plane (the far plane)
  float far_z = 1.0f;               // farthest pixel sample depth
  float light_max_z = 0.0f;         // deepest light point (0; r for a sphere)
  float light_min_z = 0.0f;         // shallowest light point (0; −r for a sphere)
  std::vector<Vec3> light_corners;  // light-space corners used for the extrusion (1, 4 or 8)
  int res_x = 1, res_y = 1;         // grid resolution in cells
  Vec2 grid_lo{0.0f};               // projected-plane coordinates of the grid's lower corner
  Vec2 cell_scale{1.0f};            // cells per projected-plane unit

  /// Grid-plane coordinates, in cell units (not clamped).
  Vec2 project_cells(const Vec3& q) const {
    const float s = (plane_z - eye.z) / (q.z - eye.z);
    return Vec2((eye.x + (q.x - eye.x) * s - grid_lo.x) * cell_scale.x,
                (eye.y + (q.y - eye.y) * s - grid_lo.y) * cell_scale.y);
  }
  /// The cell a sample falls in (clamped to the grid).
  int cell_of(const Vec3& q) const;
  int cell_count() const { return res_x * res_y; }
};

/// The grid resolution (cells per side) for option value `option` on a width × height image: the
/// value itself, or for 0 ("auto") one cell per 8 × 8 image pixels, max(width, height) / 8 and at
/// least 16. Where the grid is finer than that, its pairs and their sort grow with the cells while
/// the per-pixel work hardly shrinks: the best resolution found over five models grew with the
/// image (256²: 32–48, 512²: 48–64, 1024²: 64–128).
int grid_resolution(int option, int width, int height);

/// Builds C from the pixel samples (light space, all z ≥ 0 on this side) [Wang 2014 §3.1, §4.2]:
/// the eye on the line from the centre of the 3D AABB of samples and light corners toward the
/// light centre, `eye_distance` × light diagonal behind the light (the light point itself for a
/// point light: the irregular z-buffer limit of §3.1); grid plane = far plane; the grid covers the
/// 2D AABB of the projected samples with `resolution`² cells.
GridCamera make_grid_camera(const LightSpace& space, const std::vector<Vec3>& light_corners,
                            float light_max_z, const std::vector<Vec3>& samples, float eye_distance,
                            int resolution);

}  // namespace penumbra::gears
