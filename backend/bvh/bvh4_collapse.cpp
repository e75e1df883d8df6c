#include "bvh/bvh4.h"

#include <algorithm>
#include <limits>

namespace obvh {
namespace {

uint32_t encodeLeaf(const Bvh2Node& leaf) {
  return Bvh4Node::kLeafFlag | (leaf.firstChildOrPrim << 4) | leaf.primCount;
}

class Collapser {
 public:
  Collapser(const BinaryBvh& binary, Bvh4& out) : binary_(binary), out_(out) {}

  // Returns the child code for binary node index.
  uint32_t collapse(uint32_t index) {
    const Bvh2Node& node = binary_.nodes[index];
    if (node.isLeaf()) return encodeLeaf(node);
    std::vector<uint32_t> children = {node.firstChildOrPrim, node.firstChildOrPrim + 1};
    while (children.size() < 4) {
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
    for (int lane = 0; lane < 4; ++lane) {
      uint32_t code = Bvh4Node::kEmptyChild;
      // Unused lanes get NaN bounds: every slab comparison with NaN fails, so no ray enters them
      // (an inverted inf box would not do: its slab distances are -inf..+inf).
      const float nan = std::numeric_limits<float>::quiet_NaN();
      Box3f box;
      box.lower = box.upper = {nan, nan, nan};
      if (lane < int(children.size())) {
        box = binary_.nodes[children[lane]].bounds;
        code = collapse(children[lane]);
      }
      Bvh4Node& n = out_.nodes[nodeIndex];  // re-fetched: recursion may have grown the vector
      for (int axis = 0; axis < 3; ++axis) {
        n.bounds[axis * 2][lane] = box.lower[axis];
        n.bounds[axis * 2 + 1][lane] = box.upper[axis];
      }
      n.child[lane] = code;
    }
    return nodeIndex;
  }

 private:
  const BinaryBvh& binary_;
  Bvh4& out_;
};

}  // namespace

Bvh4 collapseToBvh4(const BinaryBvh& binary) {
  Bvh4 out;
  if (binary.empty()) return out;
  out.nodes.reserve(binary.nodes.size() / 2 + 1);
  out.rootChild = Collapser(binary, out).collapse(0);
  return out;
}

}  // namespace obvh
