#include "penumbra/shadows/gears/radix_sort.hpp"

#include <algorithm>
#include <array>

#include "penumbra/core/parallel.hpp"

namespace penumbra::gears {

void radix_sort_by_cell(CellPairs& pairs, uint32_t cell_count) {
  const size_t n = pairs.size();
  if (n < 2 || cell_count < 2) return;
  int passes = 0;
  while (passes < 4 && (uint64_t{1} << (8 * passes)) < cell_count) ++passes;
  // Fixed chunking (not thread-count dependent) keeps the sort deterministic; it is stable anyway.
  const size_t chunks = std::clamp<size_t>(n / 16384, 1, 256);
  const size_t chunk_size = (n + chunks - 1) / chunks;
  CellPairs tmp(n);
  std::vector<std::array<uint32_t, 256>> offsets(chunks);
  CellPair* src = pairs.data();
  CellPair* dst = tmp.data();
  for (int pass = 0; pass < passes; ++pass) {
    const int shift = 8 * pass;
    parallel_chunks(chunks, 1, [&](size_t c0, size_t c1) {
      for (size_t c = c0; c < c1; ++c) {
        std::array<uint32_t, 256>& h = offsets[c];
        h.fill(0);
        const size_t b = c * chunk_size, e = std::min(n, b + chunk_size);
        for (size_t i = b; i < e; ++i) ++h[(src[i].cell >> shift) & 255u];
      }
    });
    uint32_t running = 0;
    for (int d = 0; d < 256; ++d)
      for (size_t c = 0; c < chunks; ++c) {
        const uint32_t count = offsets[c][d];
        offsets[c][d] = running;
        running += count;
      }
    parallel_chunks(chunks, 1, [&](size_t c0, size_t c1) {
      for (size_t c = c0; c < c1; ++c) {
        std::array<uint32_t, 256>& o = offsets[c];
        const size_t b = c * chunk_size, e = std::min(n, b + chunk_size);
        for (size_t i = b; i < e; ++i) dst[o[(src[i].cell >> shift) & 255u]++] = src[i];
      }
    });
    std::swap(src, dst);
  }
  if (src != pairs.data()) std::copy(src, src + n, pairs.data());
}

void cell_ranges(const CellPairs& sorted, uint32_t cell_count, std::vector<uint32_t>& begin,
                 std::vector<uint32_t>& end) {
  begin.assign(cell_count, 0);
  end.assign(cell_count, 0);
  const size_t n = sorted.size();
  parallel_chunks(n, 65536, [&](size_t b, size_t e) {
    for (size_t i = b; i < e; ++i) {
      const uint32_t c = sorted[i].cell;
      if (i == 0 || sorted[i - 1].cell != c) begin[c] = static_cast<uint32_t>(i);
      if (i + 1 == n || sorted[i + 1].cell != c) end[c] = static_cast<uint32_t>(i + 1);
    }
  });
}

}  // namespace penumbra::gears
