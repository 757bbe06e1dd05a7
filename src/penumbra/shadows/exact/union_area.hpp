// The measure of the light left uncovered by a set of closed chains of light-uv segments, without
// building the union's outline: the exact reference needs only that area (untextured rectangular
// lights, opaque occluders), and a scanline sweep gets it from the edges directly — no loops,
// no integer rounding of intersection points, no output polygons.
#pragma once

#include <span>

#include "penumbra/shadows/exact/projection.hpp"

namespace penumbra {

/// Area (Clipper units²) of the points of the uv square [0, kUvScale]² where the winding number
/// of `edges` is 0. `edges` must be a union of closed chains (as many edges arrive at every point
/// as leave it) lying in the square, e.g. the outlines of the projected occluder polygons, or
/// their silhouette from adjacency; opposite copies of one segment may be present (they cancel).
/// For positively oriented polygons that is the square minus the non-zero union of the polygons.
///
/// Sweep in v: between consecutive vertex ordinates the edges crossing a beam are straight, so
/// the uncovered width is piecewise linear in v with kinks only where two edges cross; beams
/// whose edges keep their order from bottom to top are integrated exactly by the midpoint rule,
/// the others are split at the crossings first. Everything in double from integer end points:
/// the result is the area of the edges' exact winding field to ~1e-16 relative (Clipper's union
/// rounds every intersection point to the integer grid, ~1e-9 of the light's side).
double uncovered_square_area(std::span<const DirectedEdge> edges);

}  // namespace penumbra
