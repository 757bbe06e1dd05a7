// Welding by position, the project's one rule for which mesh vertices are the same point: their
// coordinates are bit-identical floats after mapping −0 to +0 — no distance tolerance, so nearly
// coincident vertices (cracks of any size) stay distinct. Topology, mesh edges, the exact
// reference's caps and adjacency, and GEARS's solids all weld this way, so they agree on which
// edges are shared.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "penumbra/core/math.hpp"

namespace penumbra {

/// For every vertex, the index of the first vertex at the same position (its representative):
/// weld[i] ≤ i, and weld[i] = i for the first of each group, so the representatives are in order
/// of first appearance. Expected linear time (open addressing on a hash of the bits).
std::vector<uint32_t> weld_positions(std::span<const Vec3> positions);

}  // namespace penumbra
