// The oriented layouts (accel=obb, accel=hybrid) with four children a node: each child is bounded
// by a box in its own frame (an axis-aligned child has the identity frame and is tested exactly),
// and one SIMD pass transforms the ray into the four frames and runs the four slab tests. Leaves
// are TriangleBlock4 groups as in the wide AABB layouts. Collapsed from the binary oriented tree
// by opening, until a node holds four, the child whose box has the largest surface.
#pragma once

#include <cstdint>
#include <vector>

#include "bvh/oriented_bvh.h"
#include "bvh/triangle_block.h"
#include "bvh/wide_bvh.h"

namespace obvh {

struct alignas(64) OrientedWideNode {
  static constexpr int kWidth = 4;
  using Codes = WideNode<4>;  // child codes: node index, leaf (blocks) or empty, as in the wide AABB layout
  float axis[3][3][4];        // axis[row][component][lane]: the rows of the child's frame
  float lower[3][4], upper[3][4];  // the child's box in its frame's coordinates
  // Rounding of the transform (see oriented_box_test.h): 1 for oriented children, 0 for
  // axis-aligned ones, which the identity rows transform exactly; and the box's magnitude.
  float oriented[4];
  float magnitude[4];
  uint32_t child[4];
  int usedMask;  // lanes holding a child
};

struct OrientedWideBvh {
  std::vector<OrientedWideNode> nodes;
  std::vector<TriangleBlock4> blocks;
  uint32_t rootChild = OrientedWideNode::Codes::kEmptyChild;  // a node index, or a leaf code for a leaf root
  bool empty() const { return rootChild == OrientedWideNode::Codes::kEmptyChild; }
};

// trianglesInLeafOrder: the triangles the binary tree's leaves index (its leaves hold at most
// 4 * WideNode<4>::kMaxLeafBlocks triangles).
OrientedWideBvh collapseOrientedToWide(const OrientedBvh& tree, const StoredTriangle* trianglesInLeafOrder);

}  // namespace obvh
