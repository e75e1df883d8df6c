// Generic scalar stack traversal of a binary BVH, nearer child first. The leaf visitor tests the
// leaf's primitives (it may shrink ray.tfar) and returns true to end the traversal early.
#pragma once

#include <limits>

#include "bvh/binary_bvh.h"
#include "traversal/box_test.h"

namespace obvh {

template <typename LeafVisitor>
void traverseBvh2(const Bvh2Node* nodes, const Ray& ray, LeafVisitor&& leafVisitor) {
  constexpr int kStackSize = 128;  // builders bound the depth well below this (see binned_sah_builder)
  constexpr float kMiss = std::numeric_limits<float>::infinity();
  struct StackEntry {
    uint32_t node;
    float tEntry;
  };
  if (nodes == nullptr) return;
  const BoxRay boxRay(ray);
  if (intersectBox(boxRay, nodes[0].bounds, ray.tnear, ray.tfar) == kMiss) return;
  StackEntry stack[kStackSize];
  int top = 0;
  stack[top++] = {0, ray.tnear};
  while (top > 0) {
    const StackEntry entry = stack[--top];
    if (entry.tEntry > ray.tfar) continue;
    uint32_t current = entry.node;
    for (;;) {
      const Bvh2Node& node = nodes[current];
      if (node.isLeaf()) {
        if (leafVisitor(node)) return;
        break;
      }
      const uint32_t left = node.firstChildOrPrim, right = left + 1;
      const float tl = intersectBox(boxRay, nodes[left].bounds, ray.tnear, ray.tfar);
      const float tr = intersectBox(boxRay, nodes[right].bounds, ray.tnear, ray.tfar);
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
  }
}

}  // namespace obvh
