#version 460
// LSD radix sort, one 8-bit digit: stable scatter for devices without subgroup ballots (the others
// run radix_scatter.comp). A key's slot = the scanned count of its (digit, block) + the number of
// keys with the same digit before it in its block, counted by comparing it with every earlier key
// of the block (four digits per word): quadratic in the block size.
#include "common.glsl"

layout(push_constant) uniform Push {
  Uints keys_in;
  Uints vals_in;
  Uints keys_out;
  Uints vals_out;
  Uints hist;  // scanned
  uint n;
  uint shift;
  uint blocks;
} pc;

shared uint packed[64];  // the block's 256 digits, four per word (byte i % 4 of word i / 4)

/// Zero bytes of x (exact, no borrow between bytes).
uint zero_bytes(uint x) {
  const uint y = ~(((x & 0x7f7f7f7fu) + 0x7f7f7f7fu) | x | 0x7f7f7f7fu);
  return bitCount(y);
}

void main() {
  const uint lid = gl_LocalInvocationIndex;
  const uint i = global_id();
  const bool live = i < pc.n;
  uint key = 0u, d = 0u;
  if (live) {
    key = pc.keys_in.v[i];
    d = (key >> pc.shift) & 255u;
  }
  if (lid < 64u) packed[lid] = 0u;
  barrier();
  // Past-the-end threads are the last of the block: their (zero) digits are never counted.
  atomicOr(packed[lid >> 2u], d << (8u * (lid & 3u)));
  barrier();
  if (!live) return;
  // Rank among the block's keys with the same digit: byte-parallel compares, four per word.
  const uint spread = d * 0x01010101u;
  uint rank = 0u;
  for (uint w = 0u; w < (lid >> 2u); ++w) rank += zero_bytes(packed[w] ^ spread);
  const uint partial = lid & 3u;  // the bytes before lid in its own word
  if (partial > 0u) {
    const uint mask = (1u << (8u * partial)) - 1u;
    rank += zero_bytes((packed[lid >> 2u] ^ spread) | ~mask);
  }
  const uint slot = pc.hist.v[d * pc.blocks + group_id()] + rank;
  pc.keys_out.v[slot] = key;
  pc.vals_out.v[slot] = pc.vals_in.v[i];
}
