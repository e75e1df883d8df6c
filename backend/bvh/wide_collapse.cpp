#include <tbb/parallel_for.h>
#include <tbb/parallel_invoke.h>

#include <algorithm>
#include <limits>

#include "bvh/collapse_forest.h"
#include "bvh/wide_bvh.h"
#include "memory/huge_pages.h"

namespace obvh {
namespace {

constexpr float kInfinity = std::numeric_limits<float>::infinity();

// Writes wide nodes and leaf blocks; what becomes a node's children is the caller's choice.
// Two ways: appending (each node before its subtree, blocks in the order leaves are written), or
// into storage sized beforehand at positions the caller computed, which lets subtrees be written
// in parallel.
template <int N>
class WideWriter {
 public:
  WideWriter(const BinaryBvh& binary, TrianglesInLeafOrder triangles, WideBvh<N>& out)
      : binary_(binary), triangles_(triangles), triangleCount_(uint32_t(binary.primIndices.size())), out_(out) {}

  // A node whose first `count` lanes are the given binary nodes; emitChild(binary index) returns a
  // lane's code.
  template <typename EmitChild>
  uint32_t emitNode(const uint32_t* children, int count, EmitChild&& emitChild) {
    const uint32_t nodeIndex = uint32_t(out_.nodes.size());
    out_.nodes.emplace_back();
    uint32_t codes[N];
    for (int lane = 0; lane < count; ++lane) codes[lane] = emitChild(children[lane]);
    writeNodeAt(nodeIndex, children, count, codes);  // by index: recursion may have grown the vector
    return nodeIndex;
  }

  // Blocks are appended in depth-first order, so a subtree's triangles stay close in memory.
  uint32_t emitLeaf(uint32_t first, uint32_t count) {
    const uint32_t firstBlock = uint32_t(out_.blocks.size());
    out_.blocks.resize(out_.blocks.size() + blockCount(count));
    return writeLeafAt(firstBlock, first, count);
  }

  void resize(size_t nodes, size_t blocks) {
    reserveWithHugePages(out_.nodes, nodes);
    reserveWithHugePages(out_.blocks, blocks);
    out_.nodes.resize(nodes);
    out_.blocks.resize(blocks);
  }

  void writeNodeAt(uint32_t nodeIndex, const uint32_t* children, int count, const uint32_t* codes) {
    WideNode<N>& n = out_.nodes[nodeIndex];
    for (int lane = 0; lane < N; ++lane) {
      uint32_t code = WideNode<N>::kEmptyChild;
      // Unused lanes get NaN bounds: every slab comparison with NaN fails, so no ray enters them
      // (an inverted inf box would not do: its slab distances are -inf..+inf).
      const float nan = std::numeric_limits<float>::quiet_NaN();
      Box3f box;
      box.lower = box.upper = {nan, nan, nan};
      if (lane < count) {
        box = binary_.nodes[children[lane]].bounds;
        code = codes[lane];
      }
      for (int axis = 0; axis < 3; ++axis) {
        n.bounds[axis * 2][lane] = box.lower[axis];
        n.bounds[axis * 2 + 1][lane] = box.upper[axis];
      }
      n.child[lane] = code;
    }
  }

  uint32_t writeLeafAt(uint32_t firstBlock, uint32_t first, uint32_t count) {
    prefetchTriangles(first + count);
    for (uint32_t b = 0; b < blockCount(count); ++b)
      out_.blocks[firstBlock + b].fill(triangles_, first + 4 * b, int(std::min<uint32_t>(4, count - 4 * b)));
    return WideNode<N>::kLeafFlag | (firstBlock << 4) | blockCount(count);
  }

  // Starts loading the triangles from `next` on, which the leaf written after this one reads
  // (leaves are written in leaf order, each a contiguous range): read through primIndices, the
  // collected triangles are scattered, and the block fill waited on every one of them (a third of
  // the writer's samples on the stores right after their loads, perf, bunny).
  void prefetchTriangles(uint32_t next) const {
    const uint32_t end = std::min<uint32_t>(next + kPrefetchedTriangles, triangleCount_);
    for (uint32_t i = next; i < end; ++i) {
      const char* p = reinterpret_cast<const char*>(&triangles_[i]);
      __builtin_prefetch(p);
      __builtin_prefetch(p + sizeof(StoredTriangle) - 1);  // a triangle may straddle two lines
    }
  }
  static uint32_t blockCount(uint32_t prims) { return (prims + 3) / 4; }

  const BinaryBvh& binary() const { return binary_; }

 private:
  // Eight: about the next leaf's (leaves hold four triangles or fewer on the meshes measured).
  static constexpr uint32_t kPrefetchedTriangles = 8;
  const BinaryBvh& binary_;
  TrianglesInLeafOrder triangles_;
  uint32_t triangleCount_;
  WideBvh<N>& out_;
};

// Keeps the binary tree's leaves; fills a node by repeatedly opening the interior child with the
// largest surface area (the one most rays enter).
template <int N>
class GreedyCollapser {
 public:
  explicit GreedyCollapser(WideWriter<N>& writer) : writer_(writer), nodes_(writer.binary().nodes) {}

  uint32_t collapse(uint32_t index) {
    const Bvh2Node& node = nodes_[index];
    if (node.isLeaf()) return writer_.emitLeaf(node.firstChildOrPrim, node.primCount);
    uint32_t children[N];
    const int count = greedyChildrenOf<N>(*this, index, children);
    return writer_.emitNode(children, count, [this](uint32_t child) { return collapse(child); });
  }

  // Tree access for greedyChildrenOf (collapse_forest.h).
  bool isLeaf(uint32_t node) const { return nodes_[node].isLeaf(); }
  uint32_t leftChild(uint32_t node) const { return nodes_[node].firstChildOrPrim; }
  float area(uint32_t node) const { return nodes_[node].bounds.halfArea(); }

 private:
  WideWriter<N>& writer_;
  const std::vector<Bvh2Node>& nodes_;
};

// The wide tree of least SAH cost (the verbose=2 statistic: an interior node costs its area, a
// leaf its area times its four-triangle blocks) among those whose nodes are cuts of the binary
// tree; a subtree small enough may also become one leaf (Ylitie, Karras and Laine, "Efficient
// Incoherent Ray Traversal on GPUs Through Compressed Wide BVHs", HPG 2017). Bottom-up, per binary
// node n and i = 1..N: the cheapest way to stand for n's subtree with at most i wide children,
// and the choice that gives it. The greedy collapse's tree is one of the candidates, so this one
// never costs more.
template <int N>
class SahCollapser {
 public:
  SahCollapser(WideWriter<N>& writer, uint32_t maxLeafPrims)
      : writer_(writer),
        nodes_(writer.binary().nodes),
        maxLeafPrims_(std::min<uint32_t>(maxLeafPrims, 4 * WideNode<N>::kMaxLeafBlocks)) {
    const size_t count = nodes_.size();
    // Tables of tens of MB for the large meshes: huge pages spare the faults of 4 KiB first touches.
    // Every entry is written (children before parents) before it is read: no fill.
    reserveWithHugePages(plans_, count);
    reserveWithHugePages(sizes_, count);
    plans_.resize(count);
    sizes_.resize(count);
    planSubtree(0, 0);
  }

  // Writes the whole wide tree and returns the root's code. Every binary node knows the size of the
  // wide subtree it would root, so each subtree's place in the depth-first layout (a node before
  // its children's subtrees, blocks in leaf order, as an appending writer lays them out) is known
  // before it is written, and large ones are written in parallel: the same tree for any thread count.
  uint32_t write() {
    writer_.resize(sizes_[0].nodes, sizes_[0].blocks);
    return writeSubtree(0, 0, 0);
  }

  // Tree access for wideChildrenOf (collapse_forest.h). Over the greedy collapse, rays from a point
  // source inside diagonal-42k ran 3.7x as fast in its larger-first order and 2.3x in the binary
  // tree's left-to-right order (README, Performance).
  const ForestChoice<N>& choice(uint32_t node) const { return plans_[node].forest; }
  bool isLeaf(uint32_t node) const { return nodes_[node].isLeaf(); }
  uint32_t leftChild(uint32_t node) const { return nodes_[node].firstChildOrPrim; }
  float area(uint32_t node) const { return nodes_[node].bounds.halfArea(); }

 private:
  struct PrimRange {
    uint32_t first, count;
    bool contiguous;  // the subtree's primitives are primIndices[first, first + count)
  };
  // What the writer needs of a binary node, together: the writer visits the binary nodes in an
  // order their storage does not follow, and one table per field cost a cache miss per field
  // (the write of the dragon's wide tree took 75 ms with five tables).
  struct NodePlan {
    PrimRange range;
    ForestChoice<N> forest;
  };
  // The wide subtree a binary node roots when the collapse makes it a node or leaf of its own.
  struct SubtreeSize {
    uint32_t nodes, blocks;
    SubtreeSize operator+(const SubtreeSize& o) const { return {nodes + o.nodes, blocks + o.blocks}; }
  };
  // The top levels of the binary tree are planned, and their subtrees written, as parallel tasks.
  static constexpr int kParallelDepth = 6;
  static constexpr uint32_t kParallelWriteNodes = 512;

  static float blocks(uint32_t prims) { return float((prims + 3) / 4); }

  // What a parent's choice needs of a child: cost[i - 1] is the cheapest forest of at most i roots
  // standing for the child's subtree. Returned up the recursion, not kept: a table of them was as
  // large as the plans (tens of MB to fault in for the large meshes).
  // size[i - 1] is that forest's size (its roots' wide subtrees together): a node's own size then
  // comes from its children's plans, without gathering its wide children (gathered for every binary
  // node, they took about a sixth of the collapse's time, perf, dragon; the write still gathers
  // them for the nodes it writes).
  struct SubtreePlan {
    float cost[N];
    SubtreeSize size[N];
    PrimRange range;
  };

  // Children before parents.
  SubtreePlan planSubtree(uint32_t node, int depth) {
    const Bvh2Node& b = nodes_[node];
    if (b.isLeaf()) return planLeaf(node);
    const uint32_t left = b.firstChildOrPrim;
    SubtreePlan l, r;
    if (depth < kParallelDepth) {
      tbb::parallel_invoke([&] { l = planSubtree(left, depth + 1); }, [&] { r = planSubtree(left + 1, depth + 1); });
    } else {
      l = planSubtree(left, depth + 1);
      r = planSubtree(left + 1, depth + 1);
    }
    return planInterior(node, l, r);
  }

  SubtreePlan planLeaf(uint32_t node) {
    const Bvh2Node& b = nodes_[node];
    NodePlan& plan = plans_[node];
    plan.range = {b.firstChildOrPrim, b.primCount, true};
    sizes_[node] = {0, WideWriter<N>::blockCount(b.primCount)};
    SubtreePlan out;
    chooseLeaf(plan.forest, b.bounds.halfArea() * blocks(b.primCount), out.cost);
    std::fill_n(out.size, N, sizes_[node]);
    out.range = plan.range;
    return out;
  }

  SubtreePlan planInterior(uint32_t node, const SubtreePlan& l, const SubtreePlan& r) {
    const float area = nodes_[node].bounds.halfArea();
    NodePlan& plan = plans_[node];
    plan.range = {l.range.first, l.range.count + r.range.count,
                  l.range.contiguous && r.range.contiguous && l.range.first + l.range.count == r.range.first};
    const bool mergeable = plan.range.contiguous && plan.range.count <= maxLeafPrims_;
    const float asLeaf = mergeable ? area * blocks(plan.range.count) : kInfinity;
    SubtreePlan out;
    out.range = plan.range;
    chooseInterior(l.cost, r.cost, area, asLeaf, plan.forest, out.cost);
    // The forest of j roots from the children, as gatherForest assembles it.
    const auto forestSize = [&](int j) {
      const int k = plan.forest.split[j - 1];
      return l.size[k - 1] + r.size[j - k - 1];
    };
    const SubtreeSize alone = plan.forest.leafChosen ? SubtreeSize{0, WideWriter<N>::blockCount(plan.range.count)}
                                                     : SubtreeSize{1, 0} + forestSize(N);
    sizes_[node] = alone;
    for (int i = 1; i <= N; ++i) {
      const int roots = plan.forest.roots[i - 1];
      out.size[i - 1] = roots == 1 ? alone : forestSize(roots);
    }
    return out;
  }

  int wideChildren(uint32_t node, uint32_t children[N]) const { return wideChildrenOf<N>(*this, node, children); }

  uint32_t writeSubtree(uint32_t node, uint32_t nodeIndex, uint32_t firstBlock) {
    const NodePlan& plan = plans_[node];
    if (plan.forest.leafChosen) return writer_.writeLeafAt(firstBlock, plan.range.first, plan.range.count);
    uint32_t children[N], childNode[N], childBlock[N], codes[N];
    const int count = wideChildren(node, children);
    uint32_t nextNode = nodeIndex + 1, nextBlock = firstBlock;
    for (int c = 0; c < count; ++c) {
      childNode[c] = nextNode, childBlock[c] = nextBlock;
      nextNode += sizes_[children[c]].nodes, nextBlock += sizes_[children[c]].blocks;
    }
    const auto writeChild = [&](int c) { codes[c] = writeSubtree(children[c], childNode[c], childBlock[c]); };
    if (sizes_[node].nodes >= kParallelWriteNodes) {
      tbb::parallel_for(0, count, writeChild);
    } else {
      for (int c = 0; c < count; ++c) writeChild(c);
    }
    writer_.writeNodeAt(nodeIndex, children, count, codes);
    return nodeIndex;
  }

  WideWriter<N>& writer_;
  const std::vector<Bvh2Node>& nodes_;
  uint32_t maxLeafPrims_;
  UnwrittenVector<NodePlan> plans_;
  UnwrittenVector<SubtreeSize> sizes_;
};

}  // namespace

template <int N>
WideBvh<N> collapseToWide(const BinaryBvh& binary, TrianglesInLeafOrder triangles, const CollapseOptions& options) {
  WideBvh<N> out;
  if (binary.empty()) return out;
  WideWriter<N> writer(binary, triangles, out);
  if (options.method == CollapseMethod::SahOptimal) {
    out.rootChild = SahCollapser<N>(writer, options.maxLeafPrims).write();
  } else {
    reserveWithHugePages(out.nodes, binary.nodes.size() / (N / 2 + 1) + 1);
    reserveWithHugePages(out.blocks, binary.primIndices.size() / 3 + 1);
    out.rootChild = GreedyCollapser<N>(writer).collapse(0);
  }
  return out;
}

template WideBvh<4> collapseToWide<4>(const BinaryBvh&, TrianglesInLeafOrder, const CollapseOptions&);
template WideBvh<8> collapseToWide<8>(const BinaryBvh&, TrianglesInLeafOrder, const CollapseOptions&);

}  // namespace obvh
