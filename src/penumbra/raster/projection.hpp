// Perspective projection to clip space and screen, homogeneous near-plane clipping, and scan
// conversion of convex polygons — the software rasterizer shared by the object-based methods
// (shadow volumes, wedges) and the image-based ones (light-space depth maps).
//
// Points at infinity: a world vertex is homogeneous (x, y, z, w) with w = 1 for a point and
// w = 0 for a direction (a point at infinity), so shadow-volume quads and far caps are extruded
// to infinity exactly, without a "large number" [Forest 2008 App. 3.A, Everitt & Kilgard's
// infinite far plane]. Clip w is the view depth (distance along the view axis); clip z carries the
// world w, so the near plane is the linear condition w_clip ≥ near·w_world (a point at infinity is
// in front iff its direction has a positive forward component). Polygons are clipped to the
// near plane and to the four side planes (widened by a guard band): after that every vertex,
// including a point at infinity, has w_clip > 0 and a finite screen position (a vanishing point).
#pragma once

#include <array>
#include <cstdint>

#include "penumbra/core/math.hpp"
#include "penumbra/scene/camera.hpp"

namespace penumbra {

using DVec4 = glm::dvec4;

/// A pinhole projection: world → clip (x·w_ndc, y·w_ndc, 0, w = view depth) → screen pixels.
/// Screen coordinates: x right, y down, pixel (i, j) covers [i, i+1) × [j, j+1), centre at +0.5 —
/// the convention of Camera::ray_direction.
struct Projection {
  DVec3 eye{0.0};
  DVec3 right{1, 0, 0}, up{0, 1, 0}, forward{0, 0, -1};  // orthonormal, world space
  double tan_half_x = 1.0, tan_half_y = 1.0;
  int width = 1, height = 1;

  /// Homogeneous world point (w = 1) or direction (w = 0) to clip space (z = the world w).
  DVec4 to_clip(const DVec4& world) const {
    const DVec3 rel = DVec3(world) - eye * world.w;
    return {glm::dot(rel, right) / tan_half_x, glm::dot(rel, up) / tan_half_y, world.w,
            glm::dot(rel, forward)};
  }
  /// Clip (w > 0) to screen: (x, y) in pixels and z = 1/w (interpolates linearly in screen space).
  DVec3 to_screen(const DVec4& clip) const {
    const double inv_w = 1.0 / clip.w;
    return {(0.5 + 0.5 * clip.x * inv_w) * width, (0.5 - 0.5 * clip.y * inv_w) * height, inv_w};
  }
  /// World direction through screen point (sx, sy) with unit forward component.
  DVec3 direction(double sx, double sy) const {
    return forward + (2.0 * sx / width - 1.0) * tan_half_x * right +
           (1.0 - 2.0 * sy / height) * tan_half_y * up;
  }
};

/// The camera's projection (same pixel grid as the G-buffer's primary rays).
Projection camera_projection(const Camera& camera);
/// A square-pixel perspective view from `eye` along unit `forward` (any up), tan_half_y = vertical
/// half-angle tangent.
Projection look_projection(const DVec3& eye, const DVec3& forward, double tan_half_y, int width,
                           int height);

/// At most 4 input vertices + 1 per clipping plane (5 planes).
inline constexpr int kMaxClipVertices = 9;

/// Clips the convex polygon in[0..n) (clip space, n ≤ 4) to the near plane w ≥ near·w_world and
/// to |x|, |y| ≤ guard·w (Sutherland–Hodgman, guard ≥ 1 widens the side planes). Intersection
/// points are computed from the edge's endpoints in a canonical order, so two polygons sharing an
/// edge get bit-identical clipped points. Returns the output vertex count (0 if fully clipped).
int clip_polygon(const DVec4* in, int n, double near, double guard, DVec4* out);

/// A convex polygon in screen space (after clip_polygon and to_screen).
struct ScreenPolygon {
  int count = 0;
  std::array<DVec3, kMaxClipVertices> v{};  // (x, y, 1/w)
  double xmin = 0, xmax = 0, ymin = 0, ymax = 0;

  bool empty() const { return count < 3; }
};

/// Projects a homogeneous world polygon (n ≤ 4 vertices) through `proj`, clipped by clip_polygon.
/// The z of a screen vertex is 1/w_clip (meaningful for finite points).
ScreenPolygon project_polygon(const Projection& proj, const DVec4* world, int n, double near,
                              double guard = 1.01);

/// Conservative horizontal extent of the polygon over the band y ∈ [y0, y1]. False if the polygon
/// does not reach the band.
bool polygon_row_span(const ScreenPolygon& poly, double y0, double y1, double& x0, double& x1);

/// Exact scan conversion of a screen triangle: calls fn(x, y, inv_w) for every pixel whose centre
/// is inside, with the top-left fill rule (two triangles sharing an edge never both cover a pixel
/// centre on it, and never both miss it). inv_w is 1/w interpolated at the centre (perspective-
/// correct depth = 1/inv_w). Returns the facing: +1 clockwise on screen (y down), −1 counter-
/// clockwise, 0 degenerate (nothing drawn). Rows clipped to [row_begin, row_end), columns to
/// [0, width).
template <typename Fn>
int rasterize_triangle(const DVec3& a, const DVec3& b, const DVec3& c, int width, int row_begin,
                       int row_end, Fn&& fn);

/// rasterize_triangle restricted to spans of each row: spans(y, emit) calls emit(x_lo, x_hi) for
/// each column range [x_lo, x_hi] of row y worth visiting (disjoint ranges: a pixel in two is
/// drawn twice). The pixels drawn are those rasterize_triangle draws within the spans, with the
/// same inv_w, bit for bit; a caller that needs only a thin part of a large triangle (a band along
/// its edges) pays for that part instead of its area.
template <typename Spans, typename Fn>
int rasterize_triangle_spans(const DVec3& a, const DVec3& b, const DVec3& c, int width,
                             int row_begin, int row_end, Spans&& spans, Fn&& fn);

/// Calls fn(first, last) with consecutive row bands [first, last) of at most `band` rows covering
/// [0, height), in parallel (oneTBB). Each output row belongs to one band: deterministic.
template <typename Fn>
void parallel_bands(int height, int band, Fn&& fn);

}  // namespace penumbra

#include "penumbra/raster/projection_inl.hpp"
