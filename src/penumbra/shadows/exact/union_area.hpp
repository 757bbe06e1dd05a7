// The measure of the light left uncovered by a set of closed chains of light-uv segments, without
// building the union's outline: the exact reference needs only that area (untextured rectangular
// lights, opaque occluders), and a scanline sweep gets it from the edges directly — no loops,
// no integer rounding of intersection points, no output polygons.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "penumbra/shadows/exact/projection.hpp"

namespace penumbra {

/// A directed light-uv segment in Clipper units (uv × kUvScale), not rounded: (x0, y0) → (x1, y1).
struct UvEdge {
  double x0, y0, x1, y1;
};
/// The sweeps' work, summed over every sweep of one area (the square's union and, with many
/// edges, the outlines of its parts): the beams, the edges crossing each beam, and the crossings
/// of two edges found inside a beam (the swaps of integrate_by_swaps).
struct SweepWork {
  uint64_t beams = 0;
  uint64_t edge_beams = 0;
  uint64_t crossings = 0;
};

/// `edges` as UvEdges, appended to `out`.
void append_uv_edges(std::span<const DirectedEdge> edges, std::vector<UvEdge>& out);

/// Area (Clipper units²) of the points of the uv square [0, kUvScale]² where the winding number
/// of `edges` is 0. `edges` must be a union of closed chains (as many edges arrive at every point
/// as leave it), e.g. the outlines of the projected occluder polygons, or their silhouette from
/// adjacency; opposite copies of one segment may be present (they cancel). The chains may reach
/// outside the square (only the field inside it is measured). For positively oriented polygons
/// that is the square minus the non-zero union of the polygons.
///
/// Sweep in v: between consecutive vertex ordinates the edges crossing a beam are straight, so
/// the uncovered width is piecewise linear in v with kinks only where two edges cross; beams
/// whose edges keep their order from bottom to top are integrated exactly by the midpoint rule,
/// the others are split at the crossings first. Everything in double: the result is the area of
/// the edges' winding field to ~1e-16 relative (Clipper's union rounds every intersection point
/// to the integer grid, ~1e-9 of the light's side).
/// `work`, if given, grows by the sweep's work (SweepWork).
double uncovered_square_area(std::span<const UvEdge> edges, SweepWork* work = nullptr);

/// The same area, computed by divide and conquer when there are many edges: `group[i]` labels
/// edge i, and the edges of each label must form closed chains whose winding number is ≥ 0
/// everywhere (the outline of one positively oriented polygon, or of several whose shared edges
/// cancelled). Chunks of whole groups are merged pairwise, each pair replaced by the outline of
/// its union (covered_outline), so edges buried inside the union so far leave early: one sweep
/// over everything costs the product of the beams and the edges crossing each (quadratic for N
/// stacked copies of a triangle), this the sum of that over much smaller outlines. Exact like
/// the single sweep (the outlines' end points are rounded along horizontal lines only).
double uncovered_square_area(std::span<const UvEdge> edges, std::span<const uint32_t> group,
                             SweepWork* work = nullptr);

/// Above this many edges the grouped uncovered_square_area divides; chunks start at kLeafEdges.
inline constexpr size_t kDivideAboveEdges = 384;
inline constexpr size_t kLeafEdges = 32;

/// uncovered_square_area, also appending to `outline` the boundary of the region inside the
/// square where the winding number is not 0: segments whose winding field is 1 on that region
/// and 0 elsewhere in the square (the square's right side, where a region may end, is left out:
/// nothing right of it is measured).
double covered_outline(std::span<const UvEdge> edges, std::vector<UvEdge>& outline,
                       SweepWork* work = nullptr);

}  // namespace penumbra
