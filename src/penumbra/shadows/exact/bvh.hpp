// The exact reference's own bounding-volume hierarchy over its occluder triangles. The reference
// judges every other method, so it shares no candidate-search code with any of them: a bug in a
// shared BVH would otherwise cancel out of every comparison.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "penumbra/core/math.hpp"

namespace penumbra {

class ExactBvh {
 public:
  struct Node {
    // Single precision is enough: the boxes are min/max of single-precision vertices, so they are
    // exact; the culling tests that read them run in double.
    Vec3 lo{0.0f};
    Vec3 hi{0.0f};
    uint32_t first = 0;  // leaf: first slot in primitives(); inner: index of the right child
    uint32_t count = 0;  // leaf: number of primitives (> 0); inner: 0 (left child = this + 1)
  };

  /// Binned-SAH build (16 bins on each axis) over the primitives' boxes. Leaves hold at most
  /// `leaf_size` primitives unless their centroids coincide (then they cannot be separated).
  void build(const std::vector<Bounds3>& boxes, int leaf_size);

  bool empty() const { return nodes_.empty(); }
  const std::vector<Node>& nodes() const { return nodes_; }
  /// Primitive indices in leaf order (a leaf owns primitives()[first, first + count)).
  const std::vector<uint32_t>& primitives() const { return order_; }
  int depth() const { return depth_; }
  /// After the caller stored its primitives in leaf order (new index k = old primitives()[k]):
  /// primitive k is then slot k, so leaves read their primitives sequentially.
  void renumber_in_leaf_order();

  /// Depth-first traversal: visits every primitive of every leaf whose box passes
  /// `overlaps(const Node&)`, in a fixed order (results never depend on threads). `visit(prim)`
  /// returns false to stop the traversal.
  template <typename Overlaps, typename Visit>
  void traverse(Overlaps&& overlaps, Visit&& visit) const {
    if (nodes_.empty()) return;
    std::array<uint32_t, kMaxDepth + 2> stack;
    int top = 0;
    stack[top++] = 0;
    while (top > 0) {
      const uint32_t index = stack[--top];
      const Node& node = nodes_[index];
      if (!overlaps(node)) continue;
      if (node.count > 0) {
        for (uint32_t k = node.first; k < node.first + node.count; ++k) {
          if (!visit(order_[k])) return;
        }
      } else {
        stack[top++] = node.first;  // right child: visited after the left subtree
        stack[top++] = index + 1;
      }
    }
  }

  /// Like traverse, for a convex query region: `classify(const Node&, bool inside)` returns
  /// kOutside (skip the subtree), kPartial (descend) or kInside (the whole box is inside). Below
  /// a kInside node `inside` is true: the region test can be skipped (the frustum-culling
  /// shortcut), other pruning (kOutside) still applies, any other answer keeps it inside.
  /// `visit(prim, inside)` learns whether the primitive's leaf lay inside; it returns false to
  /// stop. Same order as traverse.
  static constexpr int kOutside = 0, kPartial = 1, kInside = 2;
  template <typename Classify, typename Visit>
  void traverse_classified(Classify&& classify, Visit&& visit) const {
    if (nodes_.empty()) return;
    struct Entry {
      uint32_t index;
      bool inside;
    };
    std::array<Entry, kMaxDepth + 2> stack;
    int top = 0;
    stack[top++] = {0, false};
    while (top > 0) {
      const Entry e = stack[--top];
      const Node& node = nodes_[e.index];
      const int c = classify(node, e.inside);
      if (c == kOutside) continue;
      const bool inside = e.inside || c == kInside;
      if (node.count > 0) {
        for (uint32_t k = node.first; k < node.first + node.count; ++k) {
          if (!visit(order_[k], inside)) return;
        }
      } else {
        // The right child is far from this node in memory (the left one follows it): fetch it
        // while the left subtree is visited.
        __builtin_prefetch(&nodes_[node.first]);
        stack[top++] = {node.first, inside};
        stack[top++] = {e.index + 1, inside};
      }
    }
  }

  /// The build switches from SAH to object-median splits below this depth, so the depth stays
  /// below kMaxDepth for any input and the fixed traversal stack cannot overflow.
  static constexpr int kSahDepth = 48;
  static constexpr int kMaxDepth = kSahDepth + 34;

 private:
  /// Builds the subtree of order_[begin, end) into `nodes` (its root at the current end);
  /// `max_depth` grows to its deepest leaf.
  uint32_t build_node(std::vector<Node>& nodes, int& max_depth, const std::vector<Bounds3>& boxes,
                      const std::vector<Vec3>& centroids, uint32_t begin, uint32_t end, int depth,
                      int leaf_size);

  std::vector<Node> nodes_;
  std::vector<uint32_t> order_;
  int depth_ = 0;
};

}  // namespace penumbra
