// Four-wide BVH: binary nodes collapsed by repeatedly opening the child with the largest surface
// area. Child bounds are stored as structure of arrays so one SIMD test covers all four boxes.
#pragma once

#include <cstdint>
#include <vector>

#include "bvh/binary_bvh.h"

namespace obvh {

struct alignas(16) Bvh4Node {
  // bounds[axis * 2 + 0] = lower, bounds[axis * 2 + 1] = upper, one lane per child.
  float bounds[6][4];
  uint32_t child[4];  // interior: node index; leaf: kLeafFlag | first << 4 | count; empty: kEmptyChild

  static constexpr uint32_t kLeafFlag = 0x80000000u;
  static constexpr uint32_t kEmptyChild = 0xFFFFFFFFu;
  static bool isLeaf(uint32_t c) { return (c & kLeafFlag) != 0; }
  static uint32_t leafFirst(uint32_t c) { return (c & ~kLeafFlag) >> 4; }
  static uint32_t leafCount(uint32_t c) { return c & 15u; }
};

struct Bvh4 {
  std::vector<Bvh4Node> nodes;  // nodes[0] is the root
  uint32_t rootChild = Bvh4Node::kEmptyChild;  // a leaf root is stored here instead of as a node
  bool empty() const { return rootChild == Bvh4Node::kEmptyChild; }
};

// Leaves keep their primitive ranges; maxLeafSize must be at most 15.
Bvh4 collapseToBvh4(const BinaryBvh& binary);

}  // namespace obvh
