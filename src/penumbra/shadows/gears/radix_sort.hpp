// GEARS: the parallel radix sort that inverts the (item, cell) pairs into per-cell lists
// [Wang 2014 §4.2: "sorting the array on cellID's ... begin and end indices per cell"].
#pragma once

#include <cstdint>
#include <vector>

#include "penumbra/core/uninit_vector.hpp"

namespace penumbra::gears {

struct CellPair {
  uint32_t cell;
  uint32_t item;  // triangle id or pixel index
};

/// Pair arrays are written in full right after they are sized (in parallel): not zeroed first.
using CellPairs = UninitVector<CellPair>;

/// Stable LSD radix sort on `cell` (8-bit digits, as many passes as cell_count needs), parallel
/// over fixed chunks with per-chunk histograms: the result never depends on the thread count.
void radix_sort_by_cell(CellPairs& pairs, uint32_t cell_count);

/// begin/end offsets per cell of a sorted pair array (parallel over pairs; empty cells 0, 0).
void cell_ranges(const CellPairs& sorted, uint32_t cell_count, std::vector<uint32_t>& begin,
                 std::vector<uint32_t>& end);

}  // namespace penumbra::gears
