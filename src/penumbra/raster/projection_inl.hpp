// Template bodies of projection.hpp.
#pragma once

#include <algorithm>
#include <cmath>
#include <utility>

#include "penumbra/core/parallel.hpp"

namespace penumbra {

namespace raster_detail {

/// Top-left rule on a y-down screen for an edge with direction (dx, dy) of a triangle whose edge
/// functions are made positive inside: the edge owns the centres on it iff it is a "top" edge
/// (horizontal, pointing right after orientation) or a "left" edge (pointing up).
inline bool owns_centres(double dx, double dy) {
  return dy < 0.0 || (dy == 0.0 && dx > 0.0);
}

}  // namespace raster_detail

template <typename Spans, typename Fn>
int rasterize_triangle_spans(const DVec3& a0, const DVec3& b0, const DVec3& c0, int width,
                             int row_begin, int row_end, Spans&& spans, Fn&& fn) {
  const double area = (b0.x - a0.x) * (c0.y - a0.y) - (b0.y - a0.y) * (c0.x - a0.x);
  if (!(area != 0.0) || !std::isfinite(area)) return 0;
  const int facing = area > 0.0 ? 1 : -1;
  // Orient so that the edge functions are positive inside.
  const DVec3 a = a0;
  const DVec3 b = facing > 0 ? b0 : c0;
  const DVec3 c = facing > 0 ? c0 : b0;
  const double inv_area = 1.0 / std::abs(area);
  const int y_lo =
      std::max(row_begin, static_cast<int>(std::floor(std::min({a.y, b.y, c.y}) - 0.5)));
  const int y_hi =
      std::min(row_end - 1, static_cast<int>(std::ceil(std::max({a.y, b.y, c.y}) - 0.5)));
  const int x_lo = std::max(0, static_cast<int>(std::floor(std::min({a.x, b.x, c.x}) - 0.5)));
  const int x_hi =
      std::min(width - 1, static_cast<int>(std::ceil(std::max({a.x, b.x, c.x}) - 0.5)));
  if (y_lo > y_hi || x_lo > x_hi) return facing;
  // Edge i opposite vertex i: e(p) = (q1 − q0) × (p − q0) with y down and clockwise winding:
  // E_ab(p) = (b.x − a.x)(p.y − a.y) − (b.y − a.y)(p.x − a.x) > 0 inside.
  // Edge i runs from vertex i+1 to vertex i+2. Its function is evaluated from the
  // lexicographically smaller endpoint and negated as needed, so the triangle on the other side of
  // a shared edge computes exactly the opposite value (watertight, no double coverage).
  const DVec3* v[3] = {&a, &b, &c};
  double bx[3], by[3], ex[3], ey[3], sign[3];
  bool owns[3];
  for (int i = 0; i < 3; ++i) {
    const DVec3& p = *v[(i + 1) % 3];
    const DVec3& q = *v[(i + 2) % 3];
    const bool p_first = p.x < q.x || (p.x == q.x && p.y < q.y);
    const DVec3& base = p_first ? p : q;
    const DVec3& other = p_first ? q : p;
    bx[i] = base.x;
    by[i] = base.y;
    ex[i] = other.x - base.x;
    ey[i] = other.y - base.y;
    sign[i] = p_first ? 1.0 : -1.0;
    owns[i] = raster_detail::owns_centres(q.x - p.x, q.y - p.y);
  }
  for (int y = y_lo; y <= y_hi; ++y) {
    const double py = y + 0.5;
    spans(y, [&](int span_lo, int span_hi) {
      for (int x = std::max(x_lo, span_lo); x <= std::min(x_hi, span_hi); ++x) {
        const double px = x + 0.5;
        double w[3];
        bool inside = true;
        for (int i = 0; i < 3 && inside; ++i) {
          w[i] = sign[i] * (ex[i] * (py - by[i]) - ey[i] * (px - bx[i]));
          inside = w[i] > 0.0 || (w[i] == 0.0 && owns[i]);
        }
        if (!inside) continue;
        const double inv_w = (w[0] * a.z + w[1] * b.z + w[2] * c.z) * inv_area;
        fn(x, y, inv_w);
      }
    });
  }
  return facing;
}

template <typename Fn>
int rasterize_triangle(const DVec3& a, const DVec3& b, const DVec3& c, int width, int row_begin,
                       int row_end, Fn&& fn) {
  const auto whole_row = [width](int, auto&& emit) { emit(0, width - 1); };
  return rasterize_triangle_spans(a, b, c, width, row_begin, row_end, whole_row,
                                  std::forward<Fn>(fn));
}

template <typename Fn>
void parallel_bands(int height, int band, Fn&& fn) {
  const int bands = (height + band - 1) / band;
  parallel_chunks(static_cast<size_t>(bands), 1, [&](size_t begin, size_t end) {
    for (size_t b = begin; b < end; ++b) {
      const int first = static_cast<int>(b) * band;
      fn(first, std::min(height, first + band));
    }
  });
}

}  // namespace penumbra
