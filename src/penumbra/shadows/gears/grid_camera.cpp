#include "penumbra/shadows/gears/grid_camera.hpp"

#include <tbb/enumerable_thread_specific.h>

#include <algorithm>
#include <cmath>

#include "penumbra/core/error.hpp"
#include "penumbra/core/parallel.hpp"

namespace penumbra::gears {

Vec3 LightSpace::to_light(const Vec3& world) const {
  const DVec3 d = DVec3(world) - DVec3(origin);
  return Vec3(static_cast<float>(glm::dot(DVec3(inv_u), d)),
              static_cast<float>(glm::dot(DVec3(inv_v), d)),
              static_cast<float>(glm::dot(DVec3(inv_n), d)));
}

namespace {

void set_inverse(LightSpace& s) {
  // Rows of M⁻¹ for M = [u v n] (columns): the reciprocal basis.
  const DVec3 u(s.axis_u), v(s.axis_v), n(s.axis_n);
  const double det = glm::dot(u, glm::cross(v, n));
  if (!(std::abs(det) > 0.0)) throw Error("gears: degenerate light frame");
  s.inv_u = Vec3(glm::cross(v, n) / det);
  s.inv_v = Vec3(glm::cross(n, u) / det);
  s.inv_n = Vec3(glm::cross(u, v) / det);
}

/// The power of two nearest to `length` (1 for 0 or non-finite): a unit that rescales the light
/// space exactly, without rounding any coordinate.
float power_of_two_near(float length) {
  if (!(length > 0.0f) || !std::isfinite(length)) return 1.0f;
  return std::exp2(std::round(std::log2(length)));
}

}  // namespace

LightSpace make_light_space(const Light& light, const LightFrame& frame, const Vec3& toward,
                            int side) {
  LightSpace s;
  const float sgn = side < 0 ? -1.0f : 1.0f;
  switch (light.shape) {
    case LightShape::rect:
    case LightShape::disk:
      s.origin = frame.corner;
      s.axis_u = frame.edge_u;
      s.axis_v = frame.edge_v;
      s.axis_n = sgn *
                 power_of_two_near(std::max(glm::length(frame.edge_u), glm::length(frame.edge_v))) *
                 frame.emit_normal;
      break;
    case LightShape::point:
    case LightShape::sphere: {
      const Vec3 n = glm::length(toward) > 0.0f ? glm::normalize(toward) : Vec3(0.0f, -1.0f, 0.0f);
      Vec3 t, b;
      orthonormal_basis(n, t, b);
      const float r = light.shape == LightShape::sphere ? light.radius : 0.5f;
      const float unit =
          power_of_two_near(light.shape == LightShape::sphere ? 2.0f * r : glm::length(toward));
      s.axis_u = (light.shape == LightShape::sphere ? 2.0f * r : unit) * t;
      s.axis_v = (light.shape == LightShape::sphere ? 2.0f * r : unit) * b;
      s.axis_n = sgn * unit * n;
      // Point light: the light is the origin itself; sphere: its centre plane spans [0,1]².
      s.origin = light.shape == LightShape::point ? light.center : light.center - r * t - r * b;
      break;
    }
  }
  set_inverse(s);
  return s;
}

int GridCamera::cell_of(const Vec3& q) const {
  const Vec2 c = project_cells(q);
  // Clamp in float first: a sample on the eye plane would project to infinity.
  const float fx = std::clamp(std::floor(c.x), 0.0f, static_cast<float>(res_x - 1));
  const float fy = std::clamp(std::floor(c.y), 0.0f, static_cast<float>(res_y - 1));
  const int cx = fx == fx ? static_cast<int>(fx) : 0;
  const int cy = fy == fy ? static_cast<int>(fy) : 0;
  return cy * res_x + cx;
}

GridCamera make_grid_camera(const LightSpace& space, const std::vector<Vec3>& light_corners,
                            float light_max_z, const std::vector<Vec3>& samples, float eye_distance,
                            int resolution) {
  GridCamera cam;
  cam.light_corners = light_corners;
  cam.light_max_z = light_max_z;
  cam.light_min_z = 0.0f;
  for (const Vec3& c : light_corners) cam.light_min_z = std::min(cam.light_min_z, c.z);
  // 3D AABB of samples and light corners (world space, where distances mean something).
  // Min/max reductions are exact, so the parallel result is the serial one.
  struct Extent {
    Bounds3 box;
    float far_z = -kInfinity;
    Vec2 lo{kInfinity}, hi{-kInfinity};
  };
  tbb::enumerable_thread_specific<Extent> parts;
  parallel_chunks(samples.size(), 16384, [&](size_t b, size_t e) {
    Extent& x = parts.local();
    for (size_t i = b; i < e; ++i) {
      x.box.extend(space.to_world(samples[i]));
      x.far_z = std::max(x.far_z, samples[i].z);
    }
  });
  Bounds3 box;
  float far_z = light_max_z;
  for (const Extent& x : parts) {
    box.extend(x.box);
    far_z = std::max(far_z, x.far_z);
  }
  Vec3 light_center_l(0.0f);
  for (const Vec3& c : light_corners) {
    box.extend(space.to_world(c));
    light_center_l += c;
  }
  light_center_l /= static_cast<float>(light_corners.size());
  light_center_l.z = 0.0f;
  cam.far_z = far_z;

  // Eye: on the line from the AABB centre O to the light centre L_m, beyond L_m by
  // eye_distance × light diagonal [Wang 2014 §3.1]. A line nearly parallel to the light plane would
  // put the eye beside the light; then the light normal is used instead.
  float diag = 0.0f;
  for (const Vec3& a : light_corners)
    for (const Vec3& b : light_corners)
      diag = std::max(diag, glm::length(space.to_world(a) - space.to_world(b)));
  const Vec3 lm = space.to_world(light_center_l);
  Vec3 dir = lm - box.center();
  const Vec3 n_world = glm::normalize(space.axis_n);
  const float len = glm::length(dir);
  dir = len > 0.0f ? dir / len : -n_world;
  if (glm::dot(dir, -n_world) < 0.25f) dir = -n_world;
  Vec3 eye = space.to_light(lm + dir * (eye_distance * diag));
  // Strictly behind every light point (a sphere's cube reaches −r).
  const float min_back = light_max_z > 0.0f ? light_max_z : 0.0f;
  if (diag > 0.0f) eye.z = std::min(eye.z, -min_back - 1e-3f * diag);
  if (light_corners.size() == 1) eye = light_corners[0];  // point light: C is the light itself
  cam.eye = eye;
  cam.plane_z = std::max(far_z, 1e-6f);

  // The grid: 2D AABB of the projected samples [Wang 2014 §4.2].
  cam.res_x = cam.res_y = std::max(1, resolution);
  cam.cell_scale = Vec2(1.0f);
  cam.grid_lo = Vec2(0.0f);
  parallel_chunks(samples.size(), 16384, [&](size_t b, size_t e) {
    Extent& x = parts.local();
    for (size_t i = b; i < e; ++i) {
      const Vec2 g = cam.project_cells(samples[i]);
      x.lo = glm::min(x.lo, g);
      x.hi = glm::max(x.hi, g);
    }
  });
  Vec2 lo(kInfinity), hi(-kInfinity);
  for (const Extent& x : parts) lo = glm::min(lo, x.lo), hi = glm::max(hi, x.hi);
  if (samples.empty()) lo = hi = Vec2(0.0f);
  const Vec2 ext = glm::max(hi - lo, Vec2(1e-12f));
  // A hair of margin so the extreme samples fall inside the last cell.
  cam.grid_lo = lo - ext * 1e-5f;
  cam.cell_scale =
      Vec2(static_cast<float>(cam.res_x), static_cast<float>(cam.res_y)) / (ext * (1.0f + 2e-5f));
  return cam;
}

int grid_resolution(int option, int width, int height) {
  if (option > 0) return option;
  return std::max(16, (std::max(width, height) + 4) / 8);
}

}  // namespace penumbra::gears
