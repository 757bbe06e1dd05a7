// Parallel loops over oneTBB. Work is split into fixed-size chunks so results never depend on the
// number of threads (each output element is written by exactly one task).
#pragma once

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <vector>

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

/// The indices i in [0, count) for which keep(i) holds, ascending: counted per fixed chunk in
/// parallel, then written in parallel at each chunk's offset.
template <typename Keep>
std::vector<uint32_t> parallel_indices(size_t count, Keep&& keep) {
  constexpr size_t kChunk = 16384;
  const size_t chunks = (count + kChunk - 1) / kChunk;
  std::vector<size_t> offset(chunks + 1, 0);
  parallel_chunks(chunks, 1, [&](size_t c0, size_t c1) {
    for (size_t c = c0; c < c1; ++c)
      for (size_t i = c * kChunk; i < std::min(count, (c + 1) * kChunk); ++i)
        offset[c + 1] += keep(i) ? 1 : 0;
  });
  for (size_t c = 0; c < chunks; ++c) offset[c + 1] += offset[c];
  std::vector<uint32_t> out(offset[chunks]);
  parallel_chunks(chunks, 1, [&](size_t c0, size_t c1) {
    for (size_t c = c0; c < c1; ++c) {
      size_t at = offset[c];
      for (size_t i = c * kChunk; i < std::min(count, (c + 1) * kChunk); ++i)
        if (keep(i)) out[at++] = static_cast<uint32_t>(i);
    }
  });
  return out;
}

}  // namespace penumbra
