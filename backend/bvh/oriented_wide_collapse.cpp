#include <algorithm>

#include "bvh/oriented_wide_bvh.h"

namespace obvh {
namespace {

float halfAreaOf(const OrientedNode& node) {
  const Vec3f d = node.upper - node.lower;
  return d.x * d.y + d.y * d.z + d.z * d.x;
}

template <int N>
class OrientedCollapse {
 public:
  OrientedCollapse(const OrientedBvh& tree, const StoredTriangle* triangles, OrientedWideBvh<N>& out)
      : tree_(tree), triangles_(triangles), out_(out) {}

  uint32_t emit(uint32_t binaryIndex) {
    const OrientedNode& node = tree_.nodes[binaryIndex];
    return node.isLeaf() ? emitLeaf(node) : emitNode(node);
  }

 private:
  uint32_t emitLeaf(const OrientedNode& leaf) {
    const uint32_t firstBlock = uint32_t(out_.blocks.size());
    const uint32_t blockCount = (leaf.primCount + 3) / 4;
    out_.blocks.resize(out_.blocks.size() + blockCount);
    for (uint32_t b = 0; b < blockCount; ++b)
      out_.blocks[firstBlock + b].fill(triangles_ + leaf.firstChildOrPrim + 4 * b,
                                       int(std::min<uint32_t>(4, leaf.primCount - 4 * b)));
    return WideNode<N>::kLeafFlag | (firstBlock << 4) | blockCount;
  }

  uint32_t emitNode(const OrientedNode& node) {
    uint32_t children[N] = {node.firstChildOrPrim, node.firstChildOrPrim + 1};
    int count = 2;
    while (count < N) {
      int widest = -1;
      for (int c = 0; c < count; ++c) {
        const OrientedNode& candidate = tree_.nodes[children[c]];
        if (!candidate.isLeaf() && (widest < 0 || halfAreaOf(candidate) > halfAreaOf(tree_.nodes[children[widest]])))
          widest = c;
      }
      if (widest < 0) break;
      const uint32_t first = tree_.nodes[children[widest]].firstChildOrPrim;
      children[widest] = first;
      children[count++] = first + 1;
    }
    const uint32_t index = uint32_t(out_.nodes.size());
    out_.nodes.emplace_back();
    uint32_t codes[N];
    for (int c = 0; c < count; ++c) codes[c] = emit(children[c]);
    OrientedWideNode<N>& wide = out_.nodes[index];  // by index: the recursion grew the vector
    for (int lane = 0; lane < N; ++lane) {
      const bool used = lane < count;
      const OrientedNode* child = used ? &tree_.nodes[children[lane]] : nullptr;
      const bool oriented = used && child->oriented();
      for (int row = 0; row < 3; ++row) {
        for (int component = 0; component < 3; ++component) {
          const float identity = row == component ? 1.f : 0.f;
          wide.axis[row][component][lane] = oriented ? tree_.frames[child->frame].axis[row][component] : identity;
        }
        wide.lower[row][lane] = used ? child->lower[row] : 0.f;
        wide.upper[row][lane] = used ? child->upper[row] : 0.f;
      }
      wide.oriented[lane] = oriented ? 1.f : 0.f;
      wide.magnitude[lane] = used ? child->magnitude : 0.f;
      wide.child[lane] = used ? codes[lane] : WideNode<N>::kEmptyChild;
    }
    wide.usedMask = (1 << count) - 1;
    return index;
  }

  const OrientedBvh& tree_;
  const StoredTriangle* triangles_;
  OrientedWideBvh<N>& out_;
};

}  // namespace

template <int N>
OrientedWideBvh<N> collapseOrientedToWide(const OrientedBvh& tree, const StoredTriangle* trianglesInLeafOrder) {
  OrientedWideBvh<N> out;
  if (tree.empty()) return out;
  out.nodes.reserve(tree.nodes.size() / 2);
  out.rootChild = OrientedCollapse<N>(tree, trianglesInLeafOrder, out).emit(0);
  return out;
}

template OrientedWideBvh<4> collapseOrientedToWide<4>(const OrientedBvh&, const StoredTriangle*);
template OrientedWideBvh<8> collapseOrientedToWide<8>(const OrientedBvh&, const StoredTriangle*);

}  // namespace obvh
