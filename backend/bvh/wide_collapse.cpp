#include <limits>

#include "bvh/wide_bvh.h"
#include "memory/huge_pages.h"

namespace obvh {
namespace {

template <int N>
class Collapser {
 public:
  Collapser(const BinaryBvh& binary, const StoredTriangle* triangles, WideBvh<N>& out)
      : binary_(binary), triangles_(triangles), out_(out) {}

  // Returns the child code for binary node index.
  uint32_t collapse(uint32_t index) {
    const Bvh2Node& node = binary_.nodes[index];
    if (node.isLeaf()) return emitLeaf(node.firstChildOrPrim, node.primCount);
    std::vector<uint32_t> children = {node.firstChildOrPrim, node.firstChildOrPrim + 1};
    while (children.size() < size_t(N)) {
      // Open the interior child with the largest surface area: it is the one most rays enter.
      int best = -1;
      float bestArea = -1.f;
      for (size_t c = 0; c < children.size(); ++c) {
        const Bvh2Node& candidate = binary_.nodes[children[c]];
        if (!candidate.isLeaf() && candidate.bounds.halfArea() > bestArea) {
          bestArea = candidate.bounds.halfArea();
          best = int(c);
        }
      }
      if (best < 0) break;
      const uint32_t opened = children[best];
      children[best] = binary_.nodes[opened].firstChildOrPrim;
      children.push_back(binary_.nodes[opened].firstChildOrPrim + 1);
    }
    const uint32_t nodeIndex = uint32_t(out_.nodes.size());
    out_.nodes.emplace_back();
    for (int lane = 0; lane < N; ++lane) {
      uint32_t code = WideNode<N>::kEmptyChild;
      // Unused lanes get NaN bounds: every slab comparison with NaN fails, so no ray enters them
      // (an inverted inf box would not do: its slab distances are -inf..+inf).
      const float nan = std::numeric_limits<float>::quiet_NaN();
      Box3f box;
      box.lower = box.upper = {nan, nan, nan};
      if (lane < int(children.size())) {
        box = binary_.nodes[children[lane]].bounds;
        code = collapse(children[lane]);
      }
      WideNode<N>& n = out_.nodes[nodeIndex];  // re-fetched: recursion may have grown the vector
      for (int axis = 0; axis < 3; ++axis) {
        n.bounds[axis * 2][lane] = box.lower[axis];
        n.bounds[axis * 2 + 1][lane] = box.upper[axis];
      }
      n.child[lane] = code;
    }
    return nodeIndex;
  }

 private:
  // Blocks are appended in depth-first order, so a subtree's triangles stay close in memory.
  uint32_t emitLeaf(uint32_t first, uint32_t count) {
    const uint32_t firstBlock = uint32_t(out_.blocks.size());
    const uint32_t blockCount = (count + 3) / 4;
    for (uint32_t b = 0; b < blockCount; ++b) {
      TriangleBlock4 block;
      for (int lane = 0; lane < 4; ++lane) {
        const uint32_t i = b * 4 + uint32_t(lane);
        if (i < count)
          block.setLane(lane, triangles_[first + i]);
        else
          block.setUnusedLane(lane, triangles_[first]);
      }
      out_.blocks.push_back(block);
    }
    return WideNode<N>::kLeafFlag | (firstBlock << 4) | blockCount;
  }

  const BinaryBvh& binary_;
  const StoredTriangle* triangles_;
  WideBvh<N>& out_;
};

}  // namespace

template <int N>
WideBvh<N> collapseToWide(const BinaryBvh& binary, const StoredTriangle* trianglesInLeafOrder) {
  WideBvh<N> out;
  if (binary.empty()) return out;
  reserveWithHugePages(out.nodes, binary.nodes.size() / (N / 2 + 1) + 1);
  reserveWithHugePages(out.blocks, binary.primIndices.size() / 3 + 1);
  out.rootChild = Collapser<N>(binary, trianglesInLeafOrder, out).collapse(0);
  return out;
}

template WideBvh<4> collapseToWide<4>(const BinaryBvh&, const StoredTriangle*);
template WideBvh<8> collapseToWide<8>(const BinaryBvh&, const StoredTriangle*);

}  // namespace obvh
