#include "penumbra/shadows/exact/union_area.hpp"

#include <algorithm>
#include <vector>

namespace penumbra {

namespace {

/// A non-horizontal edge, from its lower end: x(y) = x0 + (y − y0)·slope on [y0, y1].
struct SweepEdge {
  double y0, y1, x0, x1, slope;
  int dir;  // +1 going up, −1 going down: the winding number's step across it
};

/// An edge crossing the current beam [ya, yb]: its abscissae at both ends (xa also serves as the
/// abscissa where the width is measured) and its upper end, in 32 bytes (the sorts move these).
struct Crossing {
  double xa, xb;
  double y1;  // sweep[edge].y1
  uint32_t edge;
  int32_t dir;
};

/// integrate_by_swaps, per position in the beam's order: the winding number left of the edge
/// there, its coefficient in the uncovered width (+1: an uncovered interval ends here, −1: one
/// starts, 0: neither) and since when.
struct Coefficients {
  std::vector<int> w_left, coefficient;
  std::vector<double> since;
};

/// From ordinate y on, sweep edge `edge` has coefficient `coefficient` in the uncovered width
/// (+1 or −1: it bounds the covered region, 0: it does not).
struct Mark {
  double y;
  uint32_t edge;
  int32_t coefficient;
};

/// Collects the boundary of the covered region (winding ≠ 0) as the pieces of the sweep edges
/// whose coefficient is non-zero, each run of one edge with one coefficient as one segment,
/// directed like the outline of a positively oriented polygon, so that its winding number is 1 on
/// the covered region and 0 elsewhere: down where the region lies to its right (coefficient +1:
/// an uncovered interval ends there), up where it lies to its left. Pieces end at ordinates shared
/// by the edges they meet (beam ends, crossing ordinates), so the field is consistent line by line;
/// their abscissae there may differ by rounding, which leaves only horizontal slivers of measure
/// zero. The right side of the square is not emitted: a region reaching it stays covered to the
/// right, where nothing is measured.
struct OutlineSink {
  const std::vector<SweepEdge>* sweep = nullptr;
  std::vector<UvEdge>* out = nullptr;
  std::vector<int8_t> dir;    // per sweep edge: the direction of its open piece, 0: none
  std::vector<double> since;  // where that piece starts

  void reset(const std::vector<SweepEdge>& edges, std::vector<UvEdge>& outline) {
    sweep = &edges;
    out = &outline;
    dir.assign(edges.size(), 0);
    since.resize(edges.size());
  }
  double x_at(const SweepEdge& e, double y) const {
    return y == e.y0 ? e.x0 : y == e.y1 ? e.x1 : e.x0 + (y - e.y0) * e.slope;
  }
  void mark(uint32_t k, int coefficient, double y) {
    const int d = -coefficient;
    if (d == dir[k]) return;
    if (dir[k] != 0 && y > since[k]) {
      const SweepEdge& e = (*sweep)[k];
      const double xa = x_at(e, since[k]), xb = x_at(e, y);
      out->push_back(dir[k] > 0 ? UvEdge{xa, since[k], xb, y} : UvEdge{xb, y, xa, since[k]});
    }
    dir[k] = static_cast<int8_t>(d);
    since[k] = y;
  }
};

/// Two edges, `left` left of `right` at the beam's bottom, crossing at ordinate y.
struct Swap {
  double y;
  uint32_t left, right;
};

/// The area of one beam [ya, yb] whose edges cross: the uncovered width is
/// Σ coefficient_i · x_i(y) (+ the side when the field is 0 right of the last edge), and at a
/// crossing only the two edges that swap change coefficient, so each edge's term is integrated
/// exactly (linear x, midpoint rule) over the runs where its coefficient is constant. `active`
/// is in bottom order and ends in top order; false (area unchanged) when a swap's two edges are
/// not neighbours at its turn (several crossings at one point, or close ones that rounding
/// reordered): the caller then splits the beam.
/// With `marks`, every edge's coefficient at ya and each change at a swap is recorded there.
bool integrate_by_swaps(const std::vector<SweepEdge>& sweep, std::vector<Crossing>& active,
                        std::vector<Swap>& swaps, std::vector<uint32_t>& pos, Coefficients& co,
                        double ya, double yb, double side, int base, double& area,
                        std::vector<Mark>* marks) {
  std::sort(swaps.begin(), swaps.end(), [](const Swap& a, const Swap& b) { return a.y < b.y; });
  const size_t n = active.size();
  co.w_left.resize(n), co.coefficient.resize(n), co.since.resize(n);
  int w = base;
  for (size_t k = 0; k < n; ++k) {
    pos[active[k].edge] = static_cast<uint32_t>(k);
    co.w_left[k] = w;
    w += active[k].dir;
    co.coefficient[k] = (co.w_left[k] == 0 ? 1 : 0) - (w == 0 ? 1 : 0);
    co.since[k] = ya;
    if (marks != nullptr) marks->push_back({ya, active[k].edge, co.coefficient[k]});
  }
  double sum = 0.0;
  const auto flush = [&](size_t k, double y) {
    if (co.coefficient[k] != 0) {
      const SweepEdge& e = sweep[active[k].edge];
      const double since = co.since[k];
      sum += co.coefficient[k] * (y - since) * (e.x0 + (0.5 * (y + since) - e.y0) * e.slope);
    }
    co.since[k] = y;
  };
  for (const Swap& s : swaps) {
    const uint32_t p = pos[s.left], q = pos[s.right];
    if (q != p + 1) return false;
    flush(p, s.y);
    flush(q, s.y);
    std::swap(active[p], active[q]);
    pos[s.right] = p;
    pos[s.left] = q;
    // The winding left of position p is unchanged; right of the new left edge it steps by its dir.
    co.w_left[q] = co.w_left[p] + active[p].dir;
    co.coefficient[p] = (co.w_left[p] == 0 ? 1 : 0) - (co.w_left[q] == 0 ? 1 : 0);
    co.coefficient[q] = (co.w_left[q] == 0 ? 1 : 0) - (co.w_left[q] + active[q].dir == 0 ? 1 : 0);
    if (marks != nullptr) {
      marks->push_back({s.y, active[p].edge, co.coefficient[p]});
      marks->push_back({s.y, active[q].edge, co.coefficient[q]});
    }
  }
  for (size_t k = 0; k < n; ++k) flush(k, yb);
  area += sum + (w == 0 ? (yb - ya) * side : 0.0);
  return true;
}

/// Sorts by xa (the abscissa where the width is measured); the array is nearly sorted, so
/// insertion sort is linear in practice.
void sort_by_x(std::vector<Crossing>& active) {
  for (size_t i = 1; i < active.size(); ++i) {
    const Crossing key = active[i];
    size_t j = i;
    while (j > 0 && active[j - 1].xa > key.xa) {
      active[j] = active[j - 1];
      --j;
    }
    active[j] = key;
  }
}

/// The total length of [0, side] where the winding number is 0, from the edges crossing one
/// horizontal line, sorted by their x there (`x(c)`; those along the right side left out), and
/// the winding number `base` at the line's left end.
template <class X>
double uncovered_width(const std::vector<Crossing>& sorted, double side, X x_of, int base) {
  int w = base;
  double prev = 0.0, width = 0.0;
  for (const Crossing& c : sorted) {
    const double x = std::clamp(x_of(c), 0.0, side);
    width += w == 0 ? x - prev : 0.0;
    w += c.dir;
    prev = x;
  }
  return width + (w == 0 ? side - prev : 0.0);
}

/// Records each edge's coefficient at ordinate y from the edges sorted by their x there.
void mark_walk(const std::vector<Crossing>& sorted, double y, OutlineSink& sink) {
  int w = 0;
  for (const Crossing& c : sorted) {
    const int w_right = w + c.dir;
    sink.mark(c.edge, (w == 0 ? 1 : 0) - (w_right == 0 ? 1 : 0), y);
    w = w_right;
  }
}

}  // namespace

void append_uv_edges(std::span<const DirectedEdge> edges, std::vector<UvEdge>& out) {
  for (const DirectedEdge& e : edges)
    out.push_back({static_cast<double>(e.from.X), static_cast<double>(e.from.Y),
                   static_cast<double>(e.to.X), static_cast<double>(e.to.Y)});
}

namespace {

/// A sweep's working arrays, kept per thread (one sweep per receiver, most with few edges).
struct SweepScratch {
  struct Start {
    double y0;
    uint32_t edge;
  };
  /// The edges along the left side as steps of the winding number at u = 0 (area sweeps
  /// only): by ordinate, +dir where one begins and −dir where it ends.
  struct Step {
    double y;
    int dir;
  };
  std::vector<SweepEdge> sweep;
  std::vector<Start> order;  // the edges by lower end
  std::vector<Step> steps;
  std::vector<double> cuts;
  std::vector<Crossing> active;
  std::vector<SweepEdge> left;
  std::vector<Crossing> by_top;
  std::vector<Swap> swaps;
  std::vector<uint32_t> pos;
  Coefficients co;
  OutlineSink sink;
  std::vector<Mark> marks;

  void add(double y0, double y1, double x0, double x1, double slope, int dir) {
    order.push_back({y0, static_cast<uint32_t>(sweep.size())});
    sweep.push_back({y0, y1, x0, x1, slope, dir});
  }
};

/// `edges` as sweep edges (s.sweep, s.order by lower end): cut to the square's rows and split at
/// its sides, the parts left of it moved onto u = 0, the parts right of it dropped. With
/// `left_as_steps`, the ones on u = 0 become s.steps instead: a line's winding number at u = 0
/// is then its start, not edges it crosses (an area needs no outline there).
void make_sweep_edges(std::span<const UvEdge> edges, SweepScratch& s, bool left_as_steps) {
  const double side = kUvScale;
  s.sweep.clear();
  s.order.clear();
  s.left.clear();
  s.steps.clear();
  for (const UvEdge& e : edges) {
    if (e.y0 == e.y1) continue;  // horizontal: never crosses a line inside a beam
    const bool up = e.y0 < e.y1;
    double x0 = up ? e.x0 : e.x1, y0 = up ? e.y0 : e.y1;
    double x1 = up ? e.x1 : e.x0, y1 = up ? e.y1 : e.y0;
    if (!(y1 > 0.0 && y0 < side)) continue;  // no row of the square crosses it
    if (x0 >= side && x1 >= side) continue;  // right of the square: changes nothing in it
    const int dir = up ? 1 : -1;
    // Rows outside the square are not measured: the parts beyond them are cut off.
    const double slope = (x1 - x0) / (y1 - y0);
    if (y0 < 0.0) {
      x0 += (0.0 - y0) * slope;
      y0 = 0.0;
    }
    if (y1 > side) {
      x1 -= (y1 - side) * slope;
      y1 = side;
    }
    // The part left of the square acts on it as its shadow on u = 0; the part right of it not
    // at all. Split there, so that no edge crosses a side of the square inside a beam (the
    // uncovered width would not be linear in y there).
    const auto split_y = [&](double x) {
      return std::clamp(y0 + (x - x0) * ((y1 - y0) / (x1 - x0)), y0, y1);
    };
    if ((x0 < 0.0 && x1 > 0.0) || (x0 > 0.0 && x1 < 0.0)) {
      const double y = split_y(0.0);
      if (x0 < 0.0) {
        s.left.push_back({y0, y, 0.0, 0.0, 0.0, dir});
        x0 = 0.0;
        y0 = y;
      } else {
        s.left.push_back({y, y1, 0.0, 0.0, 0.0, dir});
        x1 = 0.0;
        y1 = y;
      }
    } else if (x0 <= 0.0 && x1 <= 0.0) {
      s.left.push_back({y0, y1, 0.0, 0.0, 0.0, dir});
      continue;
    }
    if (x0 >= side && x1 >= side) continue;  // (the rows' cut may have moved it right)
    if ((x0 < side && x1 > side) || (x0 > side && x1 < side)) {
      const double y = split_y(side);
      if (x0 > side) {
        x0 = side;
        y0 = y;
      } else {
        x1 = side;
        y1 = y;
      }
    }
    if (!(y1 > y0)) continue;
    s.add(y0, y1, x0, x1, (x1 - x0) / (y1 - y0), dir);
  }
  // Edges along the left side (one per triangle clipped there): contiguous runs of one
  // direction merged into one edge each, the same field with fewer beams.
  std::sort(s.left.begin(), s.left.end(), [](const SweepEdge& a, const SweepEdge& b) {
    return a.dir != b.dir ? a.dir < b.dir : a.y0 < b.y0;
  });
  for (size_t i = 0; i < s.left.size();) {
    SweepEdge run = s.left[i++];
    for (; i < s.left.size() && s.left[i].dir == run.dir && s.left[i].y0 == run.y1; ++i)
      run.y1 = s.left[i].y1;
    if (left_as_steps) {
      s.steps.push_back({run.y0, run.dir});
      s.steps.push_back({run.y1, -run.dir});
    } else {
      s.add(run.y0, run.y1, 0.0, 0.0, 0.0, run.dir);
    }
  }
  std::sort(s.steps.begin(), s.steps.end(),
            [](const SweepScratch::Step& a, const SweepScratch::Step& b) { return a.y < b.y; });
  std::sort(s.order.begin(), s.order.end(),
            [](const SweepScratch::Start& a, const SweepScratch::Start& b) {
              return a.y0 != b.y0 ? a.y0 < b.y0 : a.edge < b.edge;
            });
}

/// The area of beam [ya, yb] whose edges (s.active, sorted at ya) cross inside it: integrated
/// between the crossings (integrate_by_swaps), or, where that fails, by splitting the beam at
/// every crossing; added to `area` piece by piece. Leaves s.active in some order; the next beam
/// sorts it again.
void crossing_beam(SweepScratch& s, double ya, double yb, int base, std::vector<UvEdge>* outline,
                   SweepWork* work, double& area) {
  const double side = kUvScale, h = yb - ya;
  // Insertion-sort a copy by the order at yb: every swap is one pair whose order differs at
  // the two ends, i.e. that crosses inside the beam.
  s.swaps.clear();
  s.by_top.assign(s.active.begin(), s.active.end());
  for (size_t i = 1; i < s.by_top.size(); ++i) {
    const Crossing key = s.by_top[i];
    size_t j = i;
    while (j > 0 && s.by_top[j - 1].xb > key.xb) {
      const Crossing& left = s.by_top[j - 1];
      if (left.xa < key.xa) {  // strictly left at ya, strictly right at yb
        const double da = left.xa - key.xa, db = left.xb - key.xb;
        s.swaps.push_back({std::clamp(ya + h * (da / (da - db)), ya, yb), left.edge, key.edge});
      }
      s.by_top[j] = s.by_top[j - 1];
      --j;
    }
    s.by_top[j] = key;
  }
  if (work != nullptr) work->crossings += s.swaps.size();
  s.marks.clear();
  if (integrate_by_swaps(s.sweep, s.active, s.swaps, s.pos, s.co, ya, yb, side, base, area,
                         outline != nullptr ? &s.marks : nullptr)) {
    for (const Mark& m : s.marks) s.sink.mark(m.edge, m.coefficient, m.y);
    return;
  }
  // Swaps not between neighbours (several crossings at one point, or rounding reordered close
  // ones): split the beam at every crossing instead, each piece crossing-free.
  s.cuts.clear();
  for (const Swap& w : s.swaps)
    if (w.y > ya && w.y < yb) s.cuts.push_back(w.y);
  std::sort(s.cuts.begin(), s.cuts.end());
  s.cuts.push_back(yb);
  double lo = ya;
  for (const double hi : s.cuts) {
    if (!(hi > lo)) continue;
    const double mid = 0.5 * (lo + hi);
    for (Crossing& c : s.active) {  // xa as scratch: the next beam takes its xa from xb
      const SweepEdge& e = s.sweep[c.edge];
      c.xa = e.x0 + (mid - e.y0) * e.slope;
    }
    sort_by_x(s.active);
    if (outline != nullptr) mark_walk(s.active, lo, s.sink);
    area += (hi - lo) * uncovered_width(
                            s.active, side, [](const Crossing& c) { return c.xa; }, base);
    lo = hi;
  }
}

/// Moves s.active to the beam [ya, yb]: its abscissae at both ends (at ya the previous beam's
/// top; an edge that just started enters with xb at its lower end), sorted at ya with ties by
/// the order at yb. True when no two edges cross inside the beam.
bool advance_active(SweepScratch& s, double yb) {
  // End points exactly: edges meeting at a vertex then meet in x too, never a false crossing.
  for (Crossing& c : s.active) {
    const SweepEdge& e = s.sweep[c.edge];
    c.xa = c.xb;
    c.xb = yb == e.y1 ? e.x1 : e.x0 + (yb - e.y0) * e.slope;
  }
  // Nearly sorted already: the previous beam's order at its top, plus the edges that started.
  std::vector<Crossing>& active = s.active;
  for (size_t i = 1; i < active.size(); ++i) {
    const Crossing key = active[i];
    size_t j = i;
    while (j > 0 && (active[j - 1].xa > key.xa ||
                     (active[j - 1].xa == key.xa && active[j - 1].xb > key.xb))) {
      active[j] = active[j - 1];
      --j;
    }
    active[j] = key;
  }
  bool ordered = true;
  for (size_t i = 1; i < active.size(); ++i) ordered &= active[i - 1].xb <= active[i].xb;
  return ordered;
}

/// uncovered_square_area; with `outline`, also the boundary of the covered region inside the
/// square (OutlineSink) appended there.
/// `work` (if given) grows by this sweep's beams, edge-beams and crossings.
double sweep_square(std::span<const UvEdge> edges, std::vector<UvEdge>* outline, SweepWork* work) {
  const double side = kUvScale;
  thread_local SweepScratch s;
  make_sweep_edges(edges, s, outline == nullptr);
  if (s.sweep.empty() && s.steps.empty()) return side * side;
  if (s.pos.size() < s.sweep.size()) s.pos.resize(s.sweep.size());
  if (outline != nullptr) s.sink.reset(s.sweep, *outline);
  const auto lower_end = [&](size_t k) { return s.order[k].y0; };

  // Below the lowest ordinate no edge is crossed: the field is 0 (and above the highest).
  double ya =
      std::min(s.order.empty() ? side : lower_end(0), s.steps.empty() ? side : s.steps[0].y);
  double area = ya * side;
  std::vector<Crossing>& active = s.active;
  active.clear();
  size_t next = 0, next_step = 0;
  int base = 0;  // the winding number at u = 0 (s.steps)
  while (true) {
    for (; next_step < s.steps.size() && s.steps[next_step].y <= ya; ++next_step)
      base += s.steps[next_step].dir;
    // Edges ending at ya leave (in place, keeping the order), edges starting there enter; yb is
    // the next ordinate where an edge starts or ends or the left side's winding steps.
    double yb = side;
    size_t kept = 0;
    for (const Crossing& c : active) {
      if (c.y1 > ya) {
        active[kept++] = c;
        yb = std::min(yb, c.y1);
      } else if (outline != nullptr) {
        s.sink.mark(c.edge, 0, c.y1);
      }
    }
    active.resize(kept);
    for (; next < s.order.size() && lower_end(next) <= ya; ++next) {
      const uint32_t k = s.order[next].edge;
      const SweepEdge& e = s.sweep[k];
      active.push_back({e.x0, e.x0, e.y1, k, e.dir});
      yb = std::min(yb, e.y1);
    }
    if (next < s.order.size()) yb = std::min(yb, lower_end(next));
    if (next_step < s.steps.size()) yb = std::min(yb, s.steps[next_step].y);
    if (active.empty()) {
      if (next == s.order.size() && next_step == s.steps.size()) break;
      area += base == 0 ? (yb - ya) * side : 0.0;
      ya = yb;
      continue;
    }
    if (work != nullptr) {
      ++work->beams;
      work->edge_beams += active.size();
    }
    if (advance_active(s, yb)) {
      // In order at both ends, so no two edges cross inside the beam: the uncovered width is
      // linear in y there, and its value at the middle times the height is the beam's exact area.
      if (outline != nullptr) mark_walk(active, ya, s.sink);
      area += (yb - ya) *
              uncovered_width(
                  active, side, [](const Crossing& c) { return 0.5 * (c.xa + c.xb); }, base);
    } else {
      crossing_beam(s, ya, yb, base, outline, work, area);
    }
    ya = yb;
  }
  return area + (side - ya) * side;
}

}  // namespace

double uncovered_square_area(std::span<const UvEdge> edges, SweepWork* work) {
  return sweep_square(edges, nullptr, work);
}

double covered_outline(std::span<const UvEdge> edges, std::vector<UvEdge>& outline,
                       SweepWork* work) {
  return sweep_square(edges, &outline, work);
}

double uncovered_square_area(std::span<const UvEdge> edges, std::span<const uint32_t> group,
                             SweepWork* work) {
  if (edges.size() <= kDivideAboveEdges) return sweep_square(edges, nullptr, work);
  // The groups in the order of their first edge (the caller's order: neighbours in space), each
  // group's edges together; chunks of whole groups with at least kLeafEdges edges each.
  thread_local std::vector<std::pair<uint32_t, uint32_t>> by_group;  // (group, edge)
  thread_local std::vector<std::pair<uint32_t, uint32_t>> runs;      // (first edge, run start)
  thread_local std::vector<UvEdge> level, next;
  thread_local std::vector<size_t> bounds, next_bounds;  // chunk i: [bounds[i], bounds[i + 1])
  by_group.resize(edges.size());
  for (uint32_t i = 0; i < edges.size(); ++i) by_group[i] = {group[i], i};
  std::sort(by_group.begin(), by_group.end());
  runs.clear();
  for (uint32_t i = 0; i < by_group.size(); ++i)
    if (i == 0 || by_group[i].first != by_group[i - 1].first)
      runs.push_back({by_group[i].second, i});
  std::sort(runs.begin(), runs.end());
  level.clear();
  bounds.assign(1, 0);
  for (const auto& [first, start] : runs) {
    for (uint32_t i = start; i < by_group.size() && by_group[i].first == by_group[start].first; ++i)
      level.push_back(edges[by_group[i].second]);
    if (level.size() - bounds.back() >= kLeafEdges) bounds.push_back(level.size());
  }
  if (bounds.back() != level.size()) bounds.push_back(level.size());
  // Pairs of neighbouring chunks replaced by the outline of their union, level by level: each
  // chunk's field is 0 or 1 after its first merge, edges inside the union so far are gone, and
  // only the last sweep sees every chunk. A union covering the square ends it (V = 0).
  while (bounds.size() > 3) {
    next.clear();
    next_bounds.assign(1, 0);
    for (size_t c = 0; c + 1 < bounds.size(); c += 2) {
      const size_t end = bounds[std::min(c + 2, bounds.size() - 1)];
      const std::span<const UvEdge> pair(level.data() + bounds[c], end - bounds[c]);
      if (c + 2 < bounds.size()) {
        if (covered_outline(pair, next, work) <= 0.0) return 0.0;
      } else {
        next.insert(next.end(), pair.begin(), pair.end());  // the odd one out
      }
      next_bounds.push_back(next.size());
    }
    std::swap(level, next);
    std::swap(bounds, next_bounds);
  }
  return sweep_square(level, nullptr, work);
}

}  // namespace penumbra
