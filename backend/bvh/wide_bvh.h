// Wide BVHs (four or eight children a node), collapsed from a binary tree (collapseToWide).
// Child bounds are stored as structure of arrays so one SIMD
// test covers every child box; leaves reference groups of four triangles (TriangleBlock4).
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "bvh/binary_bvh.h"
#include "bvh/triangle_block.h"
#include "memory/unwritten_allocator.h"

namespace obvh {

template <int N>
struct alignas(64) WideNode {  // cache-line aligned: a node's boxes load in as few lines as possible
  static constexpr int kWidth = N;
  // bounds[axis * 2 + 0] = lower, bounds[axis * 2 + 1] = upper, one lane per child.
  float bounds[6][N];
  uint32_t child[N];  // interior: node index; leaf: kLeafFlag | firstBlock << 4 | blockCount; empty: kEmptyChild

  static constexpr uint32_t kLeafFlag = 0x80000000u;
  static constexpr uint32_t kEmptyChild = 0xFFFFFFFFu;
  static constexpr uint32_t kMaxLeafBlocks = 15;
  static bool isLeaf(uint32_t c) { return (c & kLeafFlag) != 0; }
  static uint32_t leafFirstBlock(uint32_t c) { return (c & ~kLeafFlag) >> 4; }
  static uint32_t leafBlockCount(uint32_t c) { return c & 15u; }
  Box3f childBox(int lane) const {
    Box3f box;
    box.lower = {bounds[0][lane], bounds[2][lane], bounds[4][lane]};
    box.upper = {bounds[1][lane], bounds[3][lane], bounds[5][lane]};
    return box;
  }
};

using Bvh4Node = WideNode<4>;
using Bvh8Node = WideNode<8>;

template <int N>
struct WideBvh {
  // Sized before they are written, by the collapse's parallel writers (no zero fill first).
  UnwrittenVector<WideNode<N>> nodes;  // nodes[0] is the root
  UnwrittenVector<TriangleBlock4> blocks;
  uint32_t rootChild = WideNode<N>::kEmptyChild;  // a leaf root is stored here instead of as a node
  bool empty() const { return rootChild == WideNode<N>::kEmptyChild; }
  // The union of the root node's child boxes; an empty box when the root is a leaf (or nothing).
  Box3f rootNodeBox() const {
    Box3f box;
    if (empty() || WideNode<N>::isLeaf(rootChild)) return box;
    const WideNode<N>& top = nodes[rootChild];
    for (int lane = 0; lane < N; ++lane)
      if (top.child[lane] != WideNode<N>::kEmptyChild) box.extend(top.childBox(lane));
    return box;
  }
};

// How the binary tree becomes wide: Greedy fills each node by opening the child of largest
// surface area and keeps the binary leaves; SahOptimal picks, by dynamic programming, the cut of
// least SAH cost and may merge a subtree of up to maxLeafPrims triangles into one leaf.
enum class CollapseMethod { Greedy, SahOptimal };

struct CollapseOptions {
  CollapseMethod method = CollapseMethod::Greedy;
  uint32_t maxLeafPrims = 4;  // SahOptimal: largest merged leaf (at most 4 * kMaxLeafBlocks)
};

// The binary tree's triangles in its leaf order: triangles[i], or triangles[order[i]] when the
// triangles are still in the order they were collected (order: the tree's primIndices), so that
// a scene that keeps no copy of them in leaf order need not make one for the collapse.
struct TrianglesInLeafOrder {
  const StoredTriangle* triangles = nullptr;
  const uint32_t* order = nullptr;
  TrianglesInLeafOrder(const StoredTriangle* inLeafOrder) : triangles(inLeafOrder) {}  // NOLINT: implicit
  TrianglesInLeafOrder(const StoredTriangle* collected, const uint32_t* primIndices)
      : triangles(collected), order(primIndices) {}
  const StoredTriangle& operator[](size_t i) const { return triangles[order ? order[i] : i]; }
};

// The binary tree's leaves may hold at most 4 * kMaxLeafBlocks triangles.
template <int N>
WideBvh<N> collapseToWide(const BinaryBvh& binary, TrianglesInLeafOrder triangles, const CollapseOptions& options = {});

extern template WideBvh<4> collapseToWide<4>(const BinaryBvh&, TrianglesInLeafOrder, const CollapseOptions&);
extern template WideBvh<8> collapseToWide<8>(const BinaryBvh&, TrianglesInLeafOrder, const CollapseOptions&);

}  // namespace obvh
