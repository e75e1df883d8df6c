// Scalar stack traversal of binary BVHs, nearer child first. The leaf visitor tests the
// leaf's primitives (it may shrink ray.tfar) and returns true to end the traversal early.
#pragma once

#include <limits>
#include <utility>

#include "bvh/binary_bvh.h"
#include "traversal/box_test.h"
#include "traversal/stack_entry.h"
#include "traversal/traversal_counters.h"

namespace obvh {

// Shared by the binary layouts: enter(node) returns the entry distance into a node's volume
// within [ray.tnear, ray.tfar] or +inf (and counts the test); visit(leaf) tests the leaf.
template <typename Node, typename Enter, typename LeafVisitor>
void traverseBinaryTree(const Node* nodes, const Ray& ray, TraversalCounters* counters, Enter&& enter,
                        LeafVisitor&& leafVisitor) {
  constexpr int kStackSize = 128;  // builders bound the depth well below this (see the builders)
  constexpr float kMiss = std::numeric_limits<float>::infinity();
  if (nodes == nullptr) return;
  if (enter(nodes[0]) == kMiss) return;
  StackEntry stack[kStackSize];
  int top = 0;
  // The root starts in a register, not on the stack (see traverseWide).
  uint32_t current = 0;
  for (;;) {
    for (;;) {
      const Node& node = nodes[current];
      if (node.isLeaf()) {
        if (counters) ++counters->leafVisits;
        if (leafVisitor(node)) return;
        break;
      }
      const uint32_t left = node.firstChildOrPrim, right = left + 1;
      const float tl = enter(nodes[left]);
      const float tr = enter(nodes[right]);
      if (tl != kMiss && tr != kMiss) {
        const bool leftFirst = tl <= tr;
        if (top < kStackSize) stack[top++] = {leftFirst ? right : left, leftFirst ? tr : tl};
        current = leftFirst ? left : right;
      } else if (tl != kMiss) {
        current = left;
      } else if (tr != kMiss) {
        current = right;
      } else {
        break;
      }
    }
    for (;;) {
      if (top == 0) return;
      const StackEntry entry = stack[--top];
      if (entry.t() > ray.tfar) continue;
      current = entry.child();
      break;
    }
  }
}

template <typename LeafVisitor>
void traverseBvh2(const Bvh2Node* nodes, const Ray& ray, TraversalCounters* counters, LeafVisitor&& leafVisitor) {
  const BoxRay boxRay(ray);
  traverseBinaryTree(
      nodes, ray, counters,
      [&](const Bvh2Node& node) {
        if (counters) ++counters->aabbTests;
        return intersectBox(boxRay, node.bounds, ray.tnear, ray.tfar);
      },
      std::forward<LeafVisitor>(leafVisitor));
}

}  // namespace obvh

namespace obvh {
template <typename LeafVisitor>
void traverseBvh2(const Bvh2Node* nodes, const Ray& ray, LeafVisitor&& leafVisitor) {
  traverseBvh2(nodes, ray, nullptr, std::forward<LeafVisitor>(leafVisitor));
}
}  // namespace obvh
