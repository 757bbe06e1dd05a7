#include "penumbra/shadows/wedges/screen.hpp"

#include <algorithm>
#include <cmath>

namespace penumbra {

namespace {

double cross2(const DVec2& o, const DVec2& a, const DVec2& b) {
  return (a.x - o.x) * (b.y - o.y) - (a.y - o.y) * (b.x - o.x);
}

/// Andrew's monotone chain.
std::vector<DVec2> convex_hull(std::vector<DVec2> pts) {
  std::sort(pts.begin(), pts.end(),
            [](const DVec2& a, const DVec2& b) { return a.x < b.x || (a.x == b.x && a.y < b.y); });
  pts.erase(std::unique(pts.begin(), pts.end()), pts.end());
  if (pts.size() < 3) return pts;
  std::vector<DVec2> h(2 * pts.size());
  size_t k = 0;
  for (size_t i = 0; i < pts.size(); ++i) {
    while (k >= 2 && cross2(h[k - 2], h[k - 1], pts[i]) <= 0.0) --k;
    h[k++] = pts[i];
  }
  for (size_t i = pts.size() - 1, t = k + 1; i-- > 0;) {
    while (k >= t && cross2(h[k - 2], h[k - 1], pts[i]) <= 0.0) --k;
    h[k++] = pts[i];
  }
  h.resize(k - 1);
  return h;
}

}  // namespace

std::vector<DVec2> wedge_screen_hull(const WedgeScreenSetup& s, const DVec3& e0, const DVec3& e1,
                                     const std::vector<DVec3>& light_hull) {
  const DVec3 tops[2] = {e0, e1};
  return extrusion_screen_hull(s, tops, light_hull);
}

std::vector<DVec2> extrusion_screen_hull(const WedgeScreenSetup& s, std::span<const DVec3> tops,
                                         const std::vector<DVec3>& light_hull) {
  std::vector<DVec4> gen;
  gen.reserve(tops.size() * (1 + light_hull.size()));
  for (const DVec3& e : tops) gen.push_back(s.proj.to_clip(DVec4(e, 1.0)));
  for (const DVec3& x : light_hull) {
    for (const DVec3& e : tops) {
      const DVec3 dir = e - x;
      if (glm::dot(dir, dir) > 0.0) gen.push_back(s.proj.to_clip(DVec4(dir, 0.0)));
    }
  }
  // Slab: near·w_world ≤ w_clip ≤ far·w_world (clip z carries the world w).
  auto f_near = [&](const DVec4& c) { return c.w - s.near_depth * c.z; };
  auto f_far = [&](const DVec4& c) { return s.far_depth * c.z - c.w; };
  std::vector<DVec2> pts;
  auto add = [&](const DVec4& c) {
    const DVec3 p = s.proj.to_screen(c);
    // Clamp far off-screen points: the hull is only ever intersected with the screen.
    const double lim = 1e6 + 4.0 * std::max(s.proj.width, s.proj.height);
    pts.emplace_back(std::clamp(p.x, -lim, lim), std::clamp(p.y, -lim, lim));
  };
  for (const DVec4& c : gen)
    if (f_near(c) >= 0.0 && f_far(c) >= 0.0 && c.w > 0.0) add(c);
  for (size_t i = 0; i < gen.size(); ++i) {
    for (size_t j = i + 1; j < gen.size(); ++j) {
      const DVec4 &a = gen[i], &b = gen[j];
      for (int k = 0; k < 2; ++k) {
        const double fa = k == 0 ? f_near(a) : f_far(a), fb = k == 0 ? f_near(b) : f_far(b);
        if ((fa < 0.0) == (fb < 0.0) || fa == fb) continue;
        const DVec4 c = a + (fa / (fa - fb)) * (b - a);
        const double other = k == 0 ? f_far(c) : f_near(c);
        if (other >= -1e-12 * std::abs(c.w) && c.w > 0.0) add(c);
      }
    }
  }
  return convex_hull(std::move(pts));
}

bool hull_row_span(const std::vector<DVec2>& hull, double y0, double y1, double& x0, double& x1) {
  if (hull.empty()) return false;
  x0 = kInfinity;
  x1 = -kInfinity;
  const size_t n = hull.size();
  for (size_t i = 0; i < n; ++i) {
    const DVec2 &p = hull[i], &q = hull[(i + 1) % n];
    if (p.y >= y0 && p.y <= y1) {
      x0 = std::min(x0, p.x);
      x1 = std::max(x1, p.x);
    }
    for (double y : {y0, y1}) {
      if ((p.y < y) != (q.y < y)) {
        const double x = p.x + (y - p.y) / (q.y - p.y) * (q.x - p.x);
        x0 = std::min(x0, x);
        x1 = std::max(x1, x);
      }
    }
  }
  return x0 <= x1;
}

}  // namespace penumbra
