// Parallel loops over oneTBB. Work is split into fixed-size chunks so results never depend on the
// number of threads (each output element is written by exactly one task).
#pragma once

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <cstddef>

namespace penumbra {

/// Calls fn(begin, end) over [0, count) in chunks of at most `grain` items, in parallel.
template <typename Fn>
void parallel_chunks(size_t count, size_t grain, Fn&& fn) {
  tbb::parallel_for(tbb::blocked_range<size_t>(0, count, grain),
                    [&](const tbb::blocked_range<size_t>& r) { fn(r.begin(), r.end()); });
}

/// Calls fn(y) for every row y in [0, height), rows in parallel.
template <typename Fn>
void parallel_rows(int height, Fn&& fn) {
  tbb::parallel_for(tbb::blocked_range<int>(0, height, 1), [&](const tbb::blocked_range<int>& r) {
    for (int y = r.begin(); y < r.end(); ++y) fn(y);
  });
}

}  // namespace penumbra
