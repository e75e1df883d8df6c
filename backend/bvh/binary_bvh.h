// Binary BVH produced by the builders; later passes turn it into wide, OBB or hybrid layouts.
#pragma once

#include <cstdint>
#include <vector>

#include "math/vec3.h"

namespace obvh {

// 32 bytes: bounds plus either two adjacent children (primCount == 0) or a primitive range.
struct Bvh2Node {
  Box3f bounds;
  uint32_t firstChildOrPrim = 0;  // interior: left child index (right = left + 1); leaf: first prim
  uint32_t primCount = 0;         // 0 marks an interior node
  bool isLeaf() const { return primCount != 0; }
};

struct BinaryBvh {
  std::vector<Bvh2Node> nodes;           // nodes[0] is the root when not empty
  std::vector<uint32_t> primIndices;     // leaf ranges index this table, which maps to primitive ids
  bool empty() const { return nodes.empty(); }
};

}  // namespace obvh
