// What a pass over a binary tree's nodes often needs first: each node's range of leaf positions,
// its triangle count, parent and depth, and the nodes in pre-order.
#pragma once

#include <cstdint>
#include <vector>

#include "bvh/binary_bvh.h"

namespace obvh {

struct BinaryNodeInfo {
  uint32_t begin = 0, end = 0;  // range of leaf positions (primIndices) the subtree spans
  uint32_t primCount = 0;       // triangles in the subtree's leaves: end - begin when they are contiguous
  uint32_t parent = 0;
  int depth = 0;
};

// Every reachable node's info; preOrder receives the nodes, parents before their children.
std::vector<BinaryNodeInfo> binaryNodeInfos(const BinaryBvh& bvh, std::vector<uint32_t>& preOrder);

}  // namespace obvh
