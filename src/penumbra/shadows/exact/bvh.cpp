#include "penumbra/shadows/exact/bvh.hpp"

#include <tbb/parallel_invoke.h>

#include <algorithm>
#include <limits>
#include <numeric>

#include "penumbra/core/error.hpp"

namespace penumbra {

namespace {

constexpr int kBins = 16;
/// Subtrees over this many primitives build their two children in parallel (each into its own
/// node array, spliced after): the same tree as a serial build, node for node.
constexpr uint32_t kParallelBuild = 8192;

float half_area(const Bounds3& b) {
  if (b.empty()) return 0.0f;
  const Vec3 e = b.extent();
  return e.x * e.y + e.y * e.z + e.z * e.x;
}

}  // namespace

void ExactBvh::build(const std::vector<Bounds3>& boxes, int leaf_size) {
  nodes_.clear();
  order_.clear();
  depth_ = 0;
  if (boxes.empty()) return;
  if (boxes.size() >= (size_t{1} << 31))
    throw Error("exact: too many occluder triangles for the BVH");
  std::vector<Vec3> centroids(boxes.size());
  for (size_t i = 0; i < boxes.size(); ++i) centroids[i] = boxes[i].center();
  order_.resize(boxes.size());
  std::iota(order_.begin(), order_.end(), 0u);
  nodes_.reserve(2 * boxes.size() / static_cast<size_t>(std::max(1, leaf_size)) + 1);
  build_node(nodes_, depth_, boxes, centroids, 0, static_cast<uint32_t>(boxes.size()), 0,
             std::max(1, leaf_size));
}

uint32_t ExactBvh::build_node(std::vector<Node>& nodes, int& max_depth,
                              const std::vector<Bounds3>& boxes, const std::vector<Vec3>& centroids,
                              uint32_t begin, uint32_t end, int depth, int leaf_size) {
  const uint32_t index = static_cast<uint32_t>(nodes.size());
  nodes.emplace_back();
  max_depth = std::max(max_depth, depth);
  Bounds3 bounds, centroid_bounds;
  for (uint32_t k = begin; k < end; ++k) {
    bounds.extend(boxes[order_[k]]);
    centroid_bounds.extend(centroids[order_[k]]);
  }
  nodes[index].lo = bounds.lo;
  nodes[index].hi = bounds.hi;
  const uint32_t count = end - begin;
  if (count <= static_cast<uint32_t>(leaf_size)) {
    nodes[index].first = begin;
    nodes[index].count = count;
    return index;
  }

  uint32_t mid = begin;
  const Vec3 extent = centroid_bounds.extent();
  if (depth < kSahDepth) {
    // Binned SAH over all three axes (Wald 2007): cost = area(left)·n_left + area(right)·n_right.
    float best_cost = std::numeric_limits<float>::infinity();
    int best_axis = -1, best_split = 0;
    // All three axes binned in one pass over the primitives (they are read scattered).
    Bounds3 bin_bounds[3][kBins];
    uint32_t bin_count[3][kBins] = {};
    float scale[3];
    for (int axis = 0; axis < 3; ++axis)
      scale[axis] = extent[axis] > 0.0f ? static_cast<float>(kBins) / extent[axis] : 0.0f;
    for (uint32_t k = begin; k < end; ++k) {
      const uint32_t prim = order_[k];
      const Bounds3& box = boxes[prim];
      for (int axis = 0; axis < 3; ++axis) {
        const int b = std::clamp(
            static_cast<int>((centroids[prim][axis] - centroid_bounds.lo[axis]) * scale[axis]), 0,
            kBins - 1);
        bin_bounds[axis][b].extend(box);
        ++bin_count[axis][b];
      }
    }
    for (int axis = 0; axis < 3; ++axis) {
      if (!(extent[axis] > 0.0f)) continue;
      float right_area[kBins];
      uint32_t right_count[kBins];
      Bounds3 acc;
      uint32_t n = 0;
      for (int b = kBins - 1; b > 0; --b) {
        acc.extend(bin_bounds[axis][b]);
        n += bin_count[axis][b];
        right_area[b] = half_area(acc);
        right_count[b] = n;
      }
      acc = Bounds3();
      n = 0;
      for (int split = 1; split < kBins; ++split) {  // left = bins [0, split)
        acc.extend(bin_bounds[axis][split - 1]);
        n += bin_count[axis][split - 1];
        if (n == 0 || right_count[split] == 0) continue;
        const float cost = half_area(acc) * static_cast<float>(n) +
                           right_area[split] * static_cast<float>(right_count[split]);
        if (cost < best_cost) {
          best_cost = cost;
          best_axis = axis;
          best_split = split;
        }
      }
    }
    if (best_axis >= 0) {
      const float scale = static_cast<float>(kBins) / extent[best_axis];
      const auto it =
          std::partition(order_.begin() + begin, order_.begin() + end, [&](uint32_t prim) {
            const int b = static_cast<int>(
                (centroids[prim][best_axis] - centroid_bounds.lo[best_axis]) * scale);
            return std::clamp(b, 0, kBins - 1) < best_split;
          });
      mid = static_cast<uint32_t>(it - order_.begin());
    }
  }
  if (mid <= begin || mid >= end) {
    // Object-median split on the widest centroid axis: always separates, halves the count.
    int axis = 0;
    if (extent.y > extent[axis]) axis = 1;
    if (extent.z > extent[axis]) axis = 2;
    mid = begin + count / 2;
    std::nth_element(
        order_.begin() + begin, order_.begin() + mid, order_.begin() + end,
        [&](uint32_t a, uint32_t b) { return centroids[a][axis] < centroids[b][axis]; });
  }
  nodes[index].count = 0;
  if (count < kParallelBuild) {
    build_node(nodes, max_depth, boxes, centroids, begin, mid, depth + 1, leaf_size);
    nodes[index].first =
        build_node(nodes, max_depth, boxes, centroids, mid, end, depth + 1, leaf_size);
    return index;
  }
  // The children partition disjoint ranges of order_: built side by side, then spliced (an inner
  // node's right-child index moves with its subtree, a leaf's primitive range does not).
  std::vector<Node> left, right;
  int left_depth = depth, right_depth = depth;
  tbb::parallel_invoke(
      [&] { build_node(left, left_depth, boxes, centroids, begin, mid, depth + 1, leaf_size); },
      [&] { build_node(right, right_depth, boxes, centroids, mid, end, depth + 1, leaf_size); });
  max_depth = std::max({max_depth, left_depth, right_depth});
  const auto splice = [&](const std::vector<Node>& sub) {
    const uint32_t at = static_cast<uint32_t>(nodes.size());
    for (Node n : sub) {
      if (n.count == 0) n.first += at;
      nodes.push_back(n);
    }
    return at;
  };
  splice(left);
  nodes[index].first = splice(right);
  return index;
}

void ExactBvh::renumber_in_leaf_order() {
  std::iota(order_.begin(), order_.end(), 0u);
}

}  // namespace penumbra
