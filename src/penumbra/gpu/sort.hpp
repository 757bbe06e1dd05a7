// GPU building blocks of the GEARS pipeline: exclusive prefix sum and stable LSD radix sort of
// (key, value) pairs [Wang 2014 §4.2: "the triangle-cell pairs are sorted by cell with a radix
// sort"], recorded into a CommandList.
#pragma once

#include <cstdint>
#include <deque>

#include "penumbra/gpu/shaders.hpp"

namespace penumbra::gpu {

/// In-place exclusive prefix sum of n uints in `data`. Temporary buffers go to `scratch` (a deque:
/// references stay valid as it grows), which
/// must outlive the submission.
void record_exclusive_scan(Programs& programs, CommandList& cl, const Buffer& data, uint32_t n,
                           std::deque<Buffer>& scratch);

/// How a block ranks each key among its earlier keys with the same digit. Per 1024 keys, ballot
/// does 8 ballots per key and 256 digit counts per subgroup of the workgroup (8192 for lavapipe's
/// 32 subgroups of 8, 2048 for 8 of 32); compare does 4 × 256²/8 = 32768 byte-compare words.
/// Measured on lavapipe (bench_vulkan BM_RadixSort, 2^20 pairs): ballot 1.6–2.1× faster.
enum class RadixRanking {
  best,     // ballot where the device has subgroup ballots, else compare
  ballot,   // linear: 8 ballots match the digit within a subgroup, per-subgroup counts scanned
  compare,  // quadratic: every earlier key of the block compared (any device)
};

/// Stable sort of n (key, value) pairs by the low `key_bits` bits of the keys (8 bits per pass).
/// Returns true when the result is in (keys, values), false when it is in (keys_tmp, vals_tmp).
bool record_radix_sort(Programs& programs, CommandList& cl, const Buffer& keys,
                       const Buffer& values, const Buffer& keys_tmp, const Buffer& vals_tmp,
                       uint32_t n, int key_bits, std::deque<Buffer>& scratch,
                       RadixRanking ranking = RadixRanking::best);

}  // namespace penumbra::gpu
