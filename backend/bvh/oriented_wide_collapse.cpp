#include <algorithm>
#include <limits>

#include "bvh/collapse_forest.h"
#include "bvh/oriented_wide_bvh.h"

namespace obvh {
namespace {

constexpr float kInfinity = std::numeric_limits<float>::infinity();

float halfAreaOf(const OrientedNode& node) {
  const Vec3f d = node.upper - node.lower;
  return d.x * d.y + d.y * d.z + d.z * d.x;
}

// Writes wide oriented nodes and leaf blocks; which binary nodes become a node's children, and
// which subtrees become leaves, is the planner's choice.
template <int N>
class OrientedWriter {
 public:
  OrientedWriter(const OrientedBvh& tree, const StoredTriangle* triangles, OrientedWideBvh<N>& out)
      : tree_(tree), triangles_(triangles), out_(out) {}

  // Triangles [first, first + count) of the leaf order, which a leaf may hold (see collapse).
  uint32_t emitLeaf(uint32_t first, uint32_t count) {
    const uint32_t firstBlock = uint32_t(out_.blocks.size());
    const uint32_t blockCount = (count + 3) / 4;
    out_.blocks.resize(out_.blocks.size() + blockCount);
    for (uint32_t b = 0; b < blockCount; ++b)
      out_.blocks[firstBlock + b].fill(triangles_, first + 4 * b, int(std::min<uint32_t>(4, count - 4 * b)));
    return WideNode<N>::kLeafFlag | (firstBlock << 4) | blockCount;
  }

  // A node whose lanes are the given binary nodes; emitChild(binary index) returns a lane's code.
  template <typename EmitChild>
  uint32_t emitNode(const uint32_t* children, int count, EmitChild&& emitChild) {
    const uint32_t index = uint32_t(out_.nodes.size());
    out_.nodes.emplace_back();
    out_.nodes.back().inPalette = 1;
    uint32_t codes[N];
    for (int c = 0; c < count; ++c) codes[c] = emitChild(children[c]);
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
      const bool inPalette = !oriented || child->frame < tree_.paletteFrames;
      wide.paletteSlot[lane] = !oriented ? 0 : inPalette ? int32_t(child->frame + 1) : 0;
      if (used && !inPalette) wide.inPalette = 0;
      wide.oriented[lane] = oriented ? 1.f : 0.f;
      wide.magnitude[lane] = used ? child->magnitude : 0.f;
      wide.child[lane] = used ? codes[lane] : WideNode<N>::kEmptyChild;
    }
    wide.usedMask = (1 << count) - 1;
    return index;
  }

 private:
  const OrientedBvh& tree_;
  const StoredTriangle* triangles_;
  OrientedWideBvh<N>& out_;
};

// Keeps the binary tree's leaves; fills a node by repeatedly opening the interior child whose box
// has the largest surface (collapse=greedy).
template <int N>
class OrientedGreedyCollapse {
 public:
  OrientedGreedyCollapse(const OrientedBvh& tree, OrientedWriter<N>& writer) : tree_(tree), writer_(writer) {}

  uint32_t emit(uint32_t node) {
    const OrientedNode& b = tree_.nodes[node];
    if (b.isLeaf()) return writer_.emitLeaf(b.firstChildOrPrim, b.primCount);
    uint32_t children[N];
    const int count = greedyChildrenOf<N>(*this, node, children);
    return writer_.emitNode(children, count, [this](uint32_t child) { return emit(child); });
  }

  // Tree access for greedyChildrenOf (collapse_forest.h).
  bool isLeaf(uint32_t node) const { return tree_.nodes[node].isLeaf(); }
  uint32_t leftChild(uint32_t node) const { return tree_.nodes[node].firstChildOrPrim; }
  float area(uint32_t node) const { return halfAreaOf(tree_.nodes[node]); }

 private:
  const OrientedBvh& tree_;
  OrientedWriter<N>& writer_;
};

// The wide tree of least SAH cost among those whose nodes are cuts of the binary tree, a subtree of
// at most maxLeafPrims triangles (contiguous in the leaf order) possibly becoming one leaf under
// its root's box: the dynamic programme of the wide AABB layouts (collapse_forest.h), here with
// each box's area in its own frame and a node visit costed nodeCost block tests.
template <int N>
class OrientedSahCollapse {
 public:
  OrientedSahCollapse(const OrientedBvh& tree, OrientedWriter<N>& writer, uint32_t maxLeafPrims, float nodeCost)
      : tree_(tree), writer_(writer), maxLeafPrims_(maxLeafPrims), nodeCost_(nodeCost), plans_(tree.nodes.size()) {
    float costs[N];
    plan(0, costs);
  }

  uint32_t emit(uint32_t node) {
    const Plan& p = plans_[node];
    if (p.forest.leafChosen) return writer_.emitLeaf(p.first, p.count);
    uint32_t children[N];
    const int count = wideChildrenOf<N>(*this, node, children);
    return writer_.emitNode(children, count, [this](uint32_t child) { return emit(child); });
  }

  // Tree access for wideChildrenOf (collapse_forest.h).
  const ForestChoice<N>& choice(uint32_t node) const { return plans_[node].forest; }
  bool isLeaf(uint32_t node) const { return tree_.nodes[node].isLeaf(); }
  uint32_t leftChild(uint32_t node) const { return tree_.nodes[node].firstChildOrPrim; }
  float area(uint32_t node) const { return halfAreaOf(tree_.nodes[node]); }

 private:
  struct Plan {
    uint32_t first = 0, count = 0;
    bool contiguous = true;  // the subtree's triangles are [first, first + count) of the leaf order
    ForestChoice<N> forest;
  };

  static float blocks(uint32_t prims) { return float((prims + 3) / 4); }

  // costs[i - 1]: the cheapest forest of at most i roots standing for the subtree.
  void plan(uint32_t node, float costs[N]) {
    const OrientedNode& b = tree_.nodes[node];
    Plan& p = plans_[node];
    const float nodeArea = halfAreaOf(b);
    if (b.isLeaf()) {
      p.first = b.firstChildOrPrim, p.count = b.primCount, p.contiguous = true;
      chooseLeaf(p.forest, nodeArea * blocks(b.primCount), costs);
      return;
    }
    const uint32_t left = b.firstChildOrPrim;
    float l[N], r[N];
    plan(left, l);
    plan(left + 1, r);
    const Plan &pl = plans_[left], &pr = plans_[left + 1];
    p.first = pl.first, p.count = pl.count + pr.count;
    p.contiguous = pl.contiguous && pr.contiguous && pl.first + pl.count == pr.first;
    const float asLeaf = p.contiguous && p.count <= maxLeafPrims_ ? nodeArea * blocks(p.count) : kInfinity;
    chooseInterior(l, r, nodeCost_ * nodeArea, asLeaf, p.forest, costs);
  }

  const OrientedBvh& tree_;
  OrientedWriter<N>& writer_;
  uint32_t maxLeafPrims_;
  float nodeCost_;
  std::vector<Plan> plans_;
};

// The vertices the blocks' used lanes hold, as written: what the tree's triangle tests see.
Box3f boundsOfBlocks(const std::vector<TriangleBlock4>& blocks) {
  Box3f bounds;
  for (const TriangleBlock4& block : blocks)
    for (int lane = 0; lane < 4; ++lane)
      if ((block.usedLanes() >> lane) & 1)
        for (int k = 0; k < 3; ++k) bounds.extend(block.vertex(k, lane));
  return bounds;
}

}  // namespace

template <int N>
OrientedWideBvh<N> collapseOrientedToWide(const OrientedBvh& tree, const StoredTriangle* trianglesInLeafOrder,
                                          const OrientedCollapseOptions& options) {
  OrientedWideBvh<N> out;
  if (tree.empty()) return out;
  out.nodes.reserve(tree.nodes.size() / 2);
  if (tree.paletteFrames > 0) {
    out.hasPalette = true;
    for (int slot = 0; slot < FramePalette::kSlots; ++slot) {
      const bool framed = slot >= 1 && uint32_t(slot - 1) < tree.paletteFrames;
      for (int row = 0; row < 3; ++row)
        for (int component = 0; component < 3; ++component)
          out.palette.axis[row][component][slot] =
              framed ? tree.frames[size_t(slot - 1)].axis[row][component] : (row == component ? 1.f : 0.f);
    }
  }
  OrientedWriter<N> writer(tree, trianglesInLeafOrder, out);
  if (!options.sahOptimal) {
    out.rootChild = OrientedGreedyCollapse<N>(tree, writer).emit(0);
  } else {
    const uint32_t maxLeafPrims = std::min<uint32_t>(options.maxLeafPrims, 4 * WideNode<N>::kMaxLeafBlocks);
    out.rootChild = OrientedSahCollapse<N>(tree, writer, maxLeafPrims, options.nodeCost).emit(0);
  }
  out.bounds = boundsOfBlocks(out.blocks);
  return out;
}

template OrientedWideBvh<4> collapseOrientedToWide<4>(const OrientedBvh&, const StoredTriangle*,
                                                      const OrientedCollapseOptions&);
template OrientedWideBvh<8> collapseOrientedToWide<8>(const OrientedBvh&, const StoredTriangle*,
                                                      const OrientedCollapseOptions&);

}  // namespace obvh
