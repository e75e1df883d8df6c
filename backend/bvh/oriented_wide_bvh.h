// The oriented layouts (accel=obb, accel=hybrid) with four or eight children a node: each child is
// bounded by a box in its own frame (an axis-aligned child has the identity frame and is tested
// exactly), and one SIMD pass transforms the ray into the children's frames and runs their slab
// tests; with a frame palette (obb_palette) a node whose children all have palette frames takes
// the ray's transform from the palette instead. Leaves are TriangleBlock4 groups as in the wide
// AABB layouts. Collapsed from the binary oriented tree as the cut of least SAH cost
// (oriented_wide_collapse.cpp).
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "builders/build_options.h"
#include "bvh/oriented_bvh.h"
#include "bvh/triangle_block.h"
#include "bvh/wide_bvh.h"

namespace obvh {

template <int N>
struct alignas(64) OrientedWideNode {
  static constexpr int kWidth = N;
  using Codes = WideNode<N>;  // child codes: node index, leaf (blocks) or empty, as in the wide AABB layout
  float lower[3][N], upper[3][N];  // the child's box in its frame's coordinates
  // Rounding of the transform (see oriented_box_test.h): 1 for oriented children, 0 for
  // axis-aligned ones, which the identity rows transform exactly; and the box's magnitude.
  float oriented[N];
  float magnitude[N];
  uint32_t child[N];
  int32_t paletteSlot[N];  // with a frame palette: 0 for the identity, 1 + the frame's index
  // After the fields a palette's kernel reads: it does not read them.
  float axis[3][3][N];  // axis[row][component][lane]: the rows of the child's frame
  int usedMask;         // lanes holding a child
  int inPalette;        // every child's frame has a palette slot (else paletteSlot is void)
};
// Every lane array is loaded aligned, also by SSE kernels (a misaligned operand faults there).
static_assert(offsetof(OrientedWideNode<4>, axis) % 16 == 0 && offsetof(OrientedWideNode<8>, axis) % 32 == 0,
              "lane arrays aligned to their vectors");

// The frames every oriented node chooses from (obb_palette), one SIMD lane a slot: slot 0 is the
// identity, the frames follow, unused slots repeat the identity.
struct FramePalette {
  static constexpr int kSlots = 8;
  alignas(32) float axis[3][3][kSlots];  // axis[row][component][slot]
};
static_assert(1 + kMaxPaletteFrames <= FramePalette::kSlots, "the identity and every palette frame have a slot");

template <int N>
struct OrientedWideBvh {
  std::vector<OrientedWideNode<N>> nodes;
  std::vector<TriangleBlock4> blocks;
  uint32_t rootChild = WideNode<N>::kEmptyChild;  // a node index, or a leaf code for a leaf root
  bool hasPalette = false;                        // nodes with inPalette set take their frames from `palette`
  FramePalette palette;
  Box3f bounds;  // of every triangle in the blocks: single rays test it first (traversal/bounds_gate.h)
  bool empty() const { return rootChild == WideNode<N>::kEmptyChild; }
};

// How the binary tree's subtrees become wide nodes and leaves (collapseOrientedToWide).
struct OrientedCollapseOptions {
  bool sahOptimal = true;     // else greedy: open the widest child until the node is full
  uint32_t maxLeafPrims = 4;  // largest leaf a subtree may be merged into (at most 4 * kMaxLeafBlocks)
  float nodeCost = 1.f;       // a node visit, in triangle-block tests
};

// The wide tree of least SAH cost among the cuts of the binary tree, or the greedy one (see the .cpp).
// trianglesInLeafOrder: the triangles the binary tree's leaves index (its leaves hold at most
// 4 * WideNode<N>::kMaxLeafBlocks triangles).
template <int N>
OrientedWideBvh<N> collapseOrientedToWide(const OrientedBvh& tree, const StoredTriangle* trianglesInLeafOrder,
                                          const OrientedCollapseOptions& options = {});
extern template OrientedWideBvh<4> collapseOrientedToWide<4>(const OrientedBvh&, const StoredTriangle*,
                                                             const OrientedCollapseOptions&);
extern template OrientedWideBvh<8> collapseOrientedToWide<8>(const OrientedBvh&, const StoredTriangle*,
                                                             const OrientedCollapseOptions&);

}  // namespace obvh
