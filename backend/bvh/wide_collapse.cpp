#include <algorithm>
#include <limits>

#include "bvh/wide_bvh.h"
#include "memory/huge_pages.h"

namespace obvh {
namespace {

constexpr float kInfinity = std::numeric_limits<float>::infinity();

// Writes wide nodes and leaf blocks; what becomes a node's children is the caller's choice.
template <int N>
class WideWriter {
 public:
  WideWriter(const BinaryBvh& binary, const StoredTriangle* triangles, WideBvh<N>& out)
      : binary_(binary), triangles_(triangles), out_(out) {}

  // A node whose first `count` lanes are the given binary nodes; emitChild(binary index) returns a
  // lane's code.
  template <typename EmitChild>
  uint32_t emitNode(const uint32_t* children, int count, EmitChild&& emitChild) {
    const uint32_t nodeIndex = uint32_t(out_.nodes.size());
    out_.nodes.emplace_back();
    for (int lane = 0; lane < N; ++lane) {
      uint32_t code = WideNode<N>::kEmptyChild;
      // Unused lanes get NaN bounds: every slab comparison with NaN fails, so no ray enters them
      // (an inverted inf box would not do: its slab distances are -inf..+inf).
      const float nan = std::numeric_limits<float>::quiet_NaN();
      Box3f box;
      box.lower = box.upper = {nan, nan, nan};
      if (lane < count) {
        box = binary_.nodes[children[lane]].bounds;
        code = emitChild(children[lane]);
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

  const BinaryBvh& binary() const { return binary_; }

 private:
  const BinaryBvh& binary_;
  const StoredTriangle* triangles_;
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
    uint32_t children[N] = {node.firstChildOrPrim, node.firstChildOrPrim + 1};
    int count = 2;
    while (count < N) {
      int best = -1;
      float bestArea = -1.f;
      for (int c = 0; c < count; ++c) {
        const Bvh2Node& candidate = nodes_[children[c]];
        if (!candidate.isLeaf() && candidate.bounds.halfArea() > bestArea) {
          bestArea = candidate.bounds.halfArea();
          best = int(c);
        }
      }
      if (best < 0) break;
      const uint32_t opened = children[best];
      children[best] = nodes_[opened].firstChildOrPrim;
      children[count++] = nodes_[opened].firstChildOrPrim + 1;
    }
    return writer_.emitNode(children, count, [this](uint32_t child) { return collapse(child); });
  }

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
    plan();
  }

  uint32_t collapse(uint32_t index) {
    const NodePlan& plan = plans_[index];
    if (plan.leafChosen) return writer_.emitLeaf(plan.range.first, plan.range.count);
    uint32_t children[N];
    int count = 0;
    const uint32_t left = nodes_[index].firstChildOrPrim;
    const int k = plan.split[N - 1];
    gather(left, k, children, count);
    gather(left + 1, N - k, children, count);
    // Larger children first: the lane order decides between children entered at the same distance
    // (rays starting inside several boxes) and is the any-hit visiting order. Over the greedy
    // collapse, rays from a point source inside diagonal-42k ran 3.7x as fast in this order and
    // 2.3x in the binary tree's left-to-right order (README, Performance).
    // Insertion sort, stable: at most N entries and no allocation per node (std::stable_sort
    // allocates a buffer per call; refit commits of the dragon took up to 100 ms longer with it).
    float area[N];
    for (int c = 0; c < count; ++c) {
      const uint32_t child = children[c];
      const float a = nodes_[child].bounds.halfArea();
      int k = c;
      for (; k > 0 && area[k - 1] < a; --k) children[k] = children[k - 1], area[k] = area[k - 1];
      children[k] = child, area[k] = a;
    }
    return writer_.emitNode(children, count, [this](uint32_t child) { return collapse(child); });
  }

 private:
  struct PrimRange {
    uint32_t first = 0, count = 0;
    bool contiguous = true;  // the subtree's primitives are primIndices[first, first + count)
  };
  // What the writer needs of a binary node, together: the writer visits the binary nodes in an
  // order their storage does not follow, and one table per field cost a cache miss per field
  // (the write of the dragon's wide tree took 75 ms with five tables).
  struct NodePlan {
    PrimRange range;
    int8_t split[N];  // [j - 1]: roots from the left child in the cheapest forest of exactly j
    int8_t roots[N];  // [i - 1]: how many roots the cheapest forest of at most i has
    bool leafChosen = false;
  };

  static size_t at(uint32_t node, int i) { return size_t(node) * N + size_t(i - 1); }
  static float blocks(uint32_t prims) { return float((prims + 3) / 4); }

  void plan() {
    const size_t count = nodes_.size();
    // Tables of tens of MB for the large meshes: huge pages spare the faults of 4 KiB first touches.
    reserveWithHugePages(cost_, count * N);
    reserveWithHugePages(plans_, count);
    cost_.assign(count * N, kInfinity);
    NodePlan initial;
    std::fill_n(initial.split, N, int8_t(0));
    std::fill_n(initial.roots, N, int8_t(1));
    plans_.assign(count, initial);
    // Reverse pre-order visits children before their parent, whatever order a builder stored.
    std::vector<uint32_t> preOrder;
    reserveWithHugePages(preOrder, count);
    std::vector<uint32_t> pending{0};
    while (!pending.empty()) {
      const uint32_t node = pending.back();
      pending.pop_back();
      preOrder.push_back(node);
      if (!nodes_[node].isLeaf()) pending.push_back(nodes_[node].firstChildOrPrim), pending.push_back(nodes_[node].firstChildOrPrim + 1);
    }
    for (size_t p = preOrder.size(); p-- > 0;) {
      const uint32_t node = preOrder[p];
      const size_t n = node;
      const Bvh2Node& b = nodes_[n];
      const float area = b.bounds.halfArea();
      NodePlan& plan = plans_[n];
      if (b.isLeaf()) {
        plan.range = {b.firstChildOrPrim, b.primCount, true};
        plan.leafChosen = true;
        for (int i = 1; i <= N; ++i) cost_[at(node, i)] = area * blocks(b.primCount);
        continue;
      }
      const uint32_t left = b.firstChildOrPrim, right = left + 1;
      const PrimRange& l = plans_[left].range;
      const PrimRange& r = plans_[right].range;
      plan.range = {l.first, l.count + r.count, l.contiguous && r.contiguous && l.first + l.count == r.first};
      // Forests of j roots, j = 2..N: k of them from the left child, j - k from the right.
      float forest[N + 1];
      for (int j = 2; j <= N; ++j) {
        forest[j] = kInfinity;
        for (int k = 1; k < j; ++k) {
          const float c = cost_[at(left, k)] + cost_[at(right, j - k)];
          if (c < forest[j]) forest[j] = c, plan.split[j - 1] = int8_t(k);
        }
      }
      const float asNode = area + forest[N];
      const bool mergeable = plan.range.contiguous && plan.range.count <= maxLeafPrims_;
      const float asLeaf = mergeable ? area * blocks(plan.range.count) : kInfinity;
      plan.leafChosen = asLeaf <= asNode;
      cost_[at(node, 1)] = std::min(asLeaf, asNode);
      for (int i = 2; i <= N; ++i) {
        const float fewer = cost_[at(node, i - 1)];
        if (forest[i] < fewer) {
          cost_[at(node, i)] = forest[i], plan.roots[i - 1] = int8_t(i);
        } else {
          cost_[at(node, i)] = fewer, plan.roots[i - 1] = plan.roots[i - 2];
        }
      }
    }
  }

  // Appends the roots of the cheapest forest of at most `most` subtrees standing for `node`.
  void gather(uint32_t node, int most, uint32_t* roots, int& count) const {
    const NodePlan& plan = plans_[node];
    const int j = plan.roots[most - 1];
    if (j == 1 || nodes_[node].isLeaf()) {
      roots[count++] = node;
      return;
    }
    const int k = plan.split[j - 1];
    gather(nodes_[node].firstChildOrPrim, k, roots, count);
    gather(nodes_[node].firstChildOrPrim + 1, j - k, roots, count);
  }

  WideWriter<N>& writer_;
  const std::vector<Bvh2Node>& nodes_;
  uint32_t maxLeafPrims_;
  std::vector<float> cost_;  // [node][i - 1]: cheapest forest of at most i roots (planning only)
  std::vector<NodePlan> plans_;
};

}  // namespace

template <int N>
WideBvh<N> collapseToWide(const BinaryBvh& binary, const StoredTriangle* trianglesInLeafOrder, const CollapseOptions& options) {
  WideBvh<N> out;
  if (binary.empty()) return out;
  reserveWithHugePages(out.nodes, binary.nodes.size() / (N / 2 + 1) + 1);
  reserveWithHugePages(out.blocks, binary.primIndices.size() / 3 + 1);
  WideWriter<N> writer(binary, trianglesInLeafOrder, out);
  if (options.method == CollapseMethod::SahOptimal)
    out.rootChild = SahCollapser<N>(writer, options.maxLeafPrims).collapse(0);
  else
    out.rootChild = GreedyCollapser<N>(writer).collapse(0);
  return out;
}

template WideBvh<4> collapseToWide<4>(const BinaryBvh&, const StoredTriangle*, const CollapseOptions&);
template WideBvh<8> collapseToWide<8>(const BinaryBvh&, const StoredTriangle*, const CollapseOptions&);

}  // namespace obvh
