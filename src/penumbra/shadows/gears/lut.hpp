// GEARS LUT rasterization [Wang 2014 §4.3, Table 3–4; after Eisemann & Décoret 2007 and Sintorn et
// al. 2008]: a 2D table indexed by a quantized line in light uv (direction, offset) holding the
// bitmask of the samples on its positive side. A triangle's coverage is the AND of its four lines'
// masks. Works for any shared sample positions (irregular patterns too); approximate within one
// table bin of each line (the error the paper's Table 4 reports).
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "penumbra/core/math.hpp"

namespace penumbra::gears {

class EdgeLut {
 public:
  /// `samples`: light uv positions (bit s = sample s); `angles` × `offsets` bins.
  EdgeLut(std::span<const Vec2> samples, int angles, int offsets);

  int words() const { return words_; }
  size_t bytes() const { return table_.size() * sizeof(uint64_t); }
  /// Mask of the samples with a + b·u + c·v ≥ 0 (quantized line).
  const uint64_t* lookup(float a, float b, float c) const;
  /// The table and its parameters, for a GPU copy of lookup().
  int angles() const { return angles_; }
  int offsets() const { return offsets_; }
  float radius() const { return radius_; }
  std::span<const uint64_t> table() const { return table_; }

 private:
  int angles_, offsets_, words_;
  float radius_;                 // farthest sample from the centre (½, ½)
  std::vector<uint64_t> table_;  // [angle][offset][word]
  std::vector<uint64_t> all_, none_;
};

}  // namespace penumbra::gears
