#include "penumbra/shadows/exact/union_area.hpp"

#include <algorithm>
#include <vector>

namespace penumbra {

namespace {

/// A non-horizontal edge, from its lower end: x(y) = x0 + (y − y0)·slope on [y0, y1].
struct SweepEdge {
  double y0, y1, x0, slope;
  int dir;  // +1 going up, −1 going down: the winding number's step across it
};

/// An edge crossing the current beam [ya, yb]: its abscissae at both ends and at the middle.
struct Crossing {
  uint32_t edge;
  int dir;
  double xa, xb, x;
};

/// Sorts by x; the array is nearly sorted from one beam to the next, so insertion sort is linear
/// in practice.
void sort_by_x(std::vector<Crossing>& active) {
  for (size_t i = 1; i < active.size(); ++i) {
    const Crossing key = active[i];
    size_t j = i;
    while (j > 0 && active[j - 1].x > key.x) {
      active[j] = active[j - 1];
      --j;
    }
    active[j] = key;
  }
}

/// The total length of [0, side] where the winding number is 0, from the edges crossing one
/// horizontal line, sorted by their x there. The steps sum to 0 (closed chains), so the field is
/// 0 again right of the last edge.
double uncovered_width(const std::vector<Crossing>& sorted, double side) {
  int w = 0;
  double prev = 0.0, width = 0.0;
  for (const Crossing& c : sorted) {
    const double x = std::clamp(c.x, 0.0, side);
    if (w == 0) width += x - prev;
    w += c.dir;
    prev = x;
  }
  return width + (side - prev);
}

}  // namespace

double uncovered_square_area(std::span<const DirectedEdge> edges) {
  const double side = kUvScale;
  thread_local std::vector<SweepEdge> sweep;
  thread_local std::vector<double> ys, cuts;
  thread_local std::vector<Crossing> active;
  sweep.clear();
  ys.clear();
  for (const DirectedEdge& e : edges) {
    if (e.from.Y == e.to.Y) continue;  // horizontal: never crosses a line inside a beam
    const bool up = e.from.Y < e.to.Y;
    const ClipperLib::IntPoint& lo = up ? e.from : e.to;
    const ClipperLib::IntPoint& hi = up ? e.to : e.from;
    const double y0 = static_cast<double>(lo.Y), y1 = static_cast<double>(hi.Y);
    const double x0 = static_cast<double>(lo.X);
    sweep.push_back({y0, y1, x0, (static_cast<double>(hi.X) - x0) / (y1 - y0), up ? 1 : -1});
    ys.push_back(y0);
    ys.push_back(y1);
  }
  if (sweep.empty()) return side * side;
  std::sort(sweep.begin(), sweep.end(),
            [](const SweepEdge& a, const SweepEdge& b) { return a.y0 < b.y0; });
  std::sort(ys.begin(), ys.end());
  ys.erase(std::unique(ys.begin(), ys.end()), ys.end());

  // Below the lowest and above the highest ordinate no edge is crossed: the field is 0.
  double area = (ys.front() + (side - ys.back())) * side;
  active.clear();
  size_t next = 0;
  for (size_t i = 0; i + 1 < ys.size(); ++i) {
    const double ya = ys[i], yb = ys[i + 1], h = yb - ya;
    // Edges ending at ya leave (in place, keeping the order), edges starting there enter.
    size_t kept = 0;
    for (const Crossing& c : active)
      if (sweep[c.edge].y1 > ya) active[kept++] = c;
    active.resize(kept);
    for (; next < sweep.size() && sweep[next].y0 <= ya; ++next)
      active.push_back({static_cast<uint32_t>(next), sweep[next].dir, 0.0, 0.0, 0.0});
    if (active.empty()) {
      area += h * side;
      continue;
    }
    for (Crossing& c : active) {
      const SweepEdge& e = sweep[c.edge];
      c.xa = e.x0 + (ya - e.y0) * e.slope;
      c.xb = e.x0 + (yb - e.y0) * e.slope;
      c.x = 0.5 * (c.xa + c.xb);
    }
    sort_by_x(active);
    bool ordered = true;
    for (size_t k = 1; k < active.size() && ordered; ++k)
      ordered = active[k - 1].xa <= active[k].xa && active[k - 1].xb <= active[k].xb;
    if (ordered) {
      // No two edges cross inside the beam: the uncovered width is linear in y there, and its
      // value at the middle times the height is the beam's exact area.
      area += h * uncovered_width(active, side);
      continue;
    }
    // Split the beam where pairs of edges cross (their order at ya and yb differs), then each
    // piece is crossing-free.
    cuts.clear();
    for (size_t a = 0; a < active.size(); ++a) {
      for (size_t b = a + 1; b < active.size(); ++b) {
        const double da = active[a].xa - active[b].xa, db = active[a].xb - active[b].xb;
        if (!((da < 0.0 && db > 0.0) || (da > 0.0 && db < 0.0))) continue;
        const double y = ya + h * (da / (da - db));
        if (y > ya && y < yb) cuts.push_back(y);
      }
    }
    std::sort(cuts.begin(), cuts.end());
    cuts.push_back(yb);
    double lo = ya;
    for (const double hi : cuts) {
      if (!(hi > lo)) continue;
      const double mid = 0.5 * (lo + hi);
      for (Crossing& c : active) {
        const SweepEdge& e = sweep[c.edge];
        c.x = e.x0 + (mid - e.y0) * e.slope;
      }
      sort_by_x(active);
      area += (hi - lo) * uncovered_width(active, side);
      lo = hi;
    }
  }
  return area;
}

}  // namespace penumbra
