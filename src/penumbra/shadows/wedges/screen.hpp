// Which pixels a wedge can touch: a conservative screen-space bound of its region, the CPU
// counterpart of rasterizing the wedge's polygons [Assarsson 2003 III §3.2; Forest 2008
// §3.1.2]. GPUs rasterize the front faces of the wedge and test the back faces per pixel; on the
// CPU we bound the whole wedge on screen and test every candidate pixel's G-buffer point against
// the wedge's planes exactly (wedges/geometry.hpp), which needs no near-plane or camera-inside-
// wedge special case (Assarsson 2003 III §5.3, Forest 2008 §3.1.3): the test is in world space, per
// point.
//
// The region S of an edge (wedges/geometry.hpp) lies in the polyhedron conv{t0, t1} + cone{t_i −
// x_k} (x_k the light hull points, t0–t1 the wedge's top edge: the edge itself for `hull`, the
// edge with its farther vertex moved toward the light centre for `paper`, which still holds S
// because e0 = e0' + (1/s − 1)·(e0' − c) and c is a convex combination of the x_k): homogeneous
// generators (t_i, 1) and (t_i − x_k, 0), i.e. the top edge extruded to infinity away from every
// light point [Forest 2008 App. 3.B]. Only points between
// the nearest and farthest G-buffer depths matter, so the polyhedron is cut to that slab of view
// depths; the extreme points of the cut polyhedron are generators inside the slab and
// intersections of generator pairs with the slab's planes. Their projections' convex hull bounds
// every pixel whose point lies in S.
#pragma once

#include <span>
#include <vector>

#include "penumbra/core/math.hpp"
#include "penumbra/raster/projection.hpp"

namespace penumbra {

struct WedgeScreenSetup {
  Projection proj;
  double near_depth = 0.0;  // view depth slab holding every active shadow origin
  double far_depth = 0.0;
};

/// The convex hull (counter-clockwise in screen pixels, x right, y down) bounding the projection
/// of the region of top edge e0–e1 (Wedge::top0, top1) for the light hull points. Empty if it
/// misses the depth slab.
std::vector<DVec2> wedge_screen_hull(const WedgeScreenSetup& setup, const DVec3& e0,
                                     const DVec3& e1, const std::vector<DVec3>& light_hull);

/// The same bound for the region conv{tops} + cone{top − x_k} of any set of top points: a soft
/// textured shadow volume's triangle (wedges/stsv.hpp) as well as a wedge's top edge.
std::vector<DVec2> extrusion_screen_hull(const WedgeScreenSetup& setup, std::span<const DVec3> tops,
                                         const std::vector<DVec3>& light_hull);

/// Horizontal extent of the convex polygon over the band y ∈ [y0, y1]; false if it misses it.
bool hull_row_span(const std::vector<DVec2>& hull, double y0, double y1, double& x0, double& x1);

}  // namespace penumbra
