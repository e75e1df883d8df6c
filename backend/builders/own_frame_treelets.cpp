#include "builders/own_frame_treelets.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <numeric>
#include <vector>

#include "bvh/binary_node_infos.h"
#include "obb/obb.h"

namespace obvh {
namespace {

Obb unite(const Obb& a, const Obb& b) {
  Obb box = a;
  for (int k = 0; k < 3; ++k) {
    box.lower[k] = std::min(a.lower[k], b.lower[k]);
    box.upper[k] = std::max(a.upper[k], b.upper[k]);
  }
  return box;
}

// The box of the points along the axes, unrounded: choosing a split needs no guarantee that the box
// holds the points (the oriented layout refits every box later, rounded outwards, which costs a
// library call a bound).
Obb boxAlong(const Vec3f axes[3], const Vec3f* points, uint32_t count) {
  Obb box;
  for (int k = 0; k < 3; ++k) {
    box.axis[k] = axes[k];
    box.lower[k] = box.upper[k] = dot(axes[k], points[0]);
    for (uint32_t i = 1; i < count; ++i) {
      const float d = dot(axes[k], points[i]);
      box.lower[k] = std::min(box.lower[k], d);
      box.upper[k] = std::max(box.upper[k], d);
    }
  }
  return box;
}

// A treelet as built: nodes in the BinaryBvh's form (children of an interior node at
// firstChildOrPrim and firstChildOrPrim + 1, leaves' ranges relative to the treelet's first
// triangle), node 0 its root, and its triangles' order.
struct Treelet {
  std::vector<Bvh2Node> nodes;
  std::vector<uint32_t> order;  // primIndices values in the new leaf order
};

// Builds a treelet top-down with a sweep SAH over its triangles' boxes in each node's own frame
// (the DiTO-14 box of the node's triangles; nodes small enough for a leaf take their parent's).
// One frame for the whole treelet found worse trees: more leaf visits a hitting ray than without
// treelets on stepped-6.6k and diagonal-42k.
class TreeletBuilder {
 public:
  TreeletBuilder(const StoredTriangle* triangles, const BuildOptions& options) : triangles_(triangles), options_(options) {}

  Treelet build(const uint32_t* primIndices, uint32_t count) {
    Treelet t;
    t.order.assign(primIndices, primIndices + count);
    t.nodes.emplace_back();
    split(t, 0, 0, count, nullptr);
    return t;
  }

 private:
  Box3f worldBounds(const uint32_t* prims, uint32_t count) const {
    Box3f box;
    for (uint32_t i = 0; i < count; ++i) {
      const StoredTriangle& tri = triangles_[prims[i]];
      for (const Vec3f& p : {tri.v0, tri.v1, tri.v2}) box.extend(p);
    }
    return box;
  }

  // Node `node` over t.order[begin, end): a leaf, or the best sweep split along one of the frame's
  // axes (by the centres of the triangles' boxes).
  void split(Treelet& t, uint32_t node, uint32_t begin, uint32_t end, const Vec3f* parentAxes) {
    const uint32_t count = end - begin;
    t.nodes[node].bounds = worldBounds(t.order.data() + begin, count);
    const auto makeLeaf = [&] {
      t.nodes[node].firstChildOrPrim = begin;
      t.nodes[node].primCount = count;
    };
    if (count == 1) return makeLeaf();
    Vec3f points[3 * kMaxTreeletTriangles];
    for (uint32_t i = 0; i < count; ++i) {
      const StoredTriangle& tri = triangles_[t.order[begin + i]];
      points[3 * i] = tri.v0, points[3 * i + 1] = tri.v1, points[3 * i + 2] = tri.v2;
    }
    const Obb all = parentAxes && int(count) <= options_.maxLeafSize ? boxAlong(parentAxes, points, 3 * count)
                                                                      : fitObb(options_.obbFit, points, 3 * count);
    const float area = all.halfArea();
    Obb boxes[kMaxTreeletTriangles];
    for (uint32_t i = 0; i < count; ++i) boxes[i] = boxAlong(all.axis, points + 3 * i, 3);
    const bool mayBeLeaf = int(count) <= options_.maxLeafSize;
    if (mayBeLeaf && !(area > 0.f)) return makeLeaf();
    // An oriented layout's node visit costs an oriented-box test. At traversalCost alone, the
    // treelets split down to single triangles, which the wide collapse merged again: the same leaf
    // visits for 4% more binary nodes to build (mixed-654k).
    const float nodeCost = options_.traversalCost * options_.obbTestCost;
    float bestCost = mayBeLeaf ? options_.intersectionCost * float(count) : std::numeric_limits<float>::infinity();
    int bestAxis = -1;
    uint32_t bestAt = 0;
    uint32_t byAxis[kMaxTreeletTriangles], best[kMaxTreeletTriangles];
    float suffixArea[kMaxTreeletTriangles];
    for (int axis = 0; axis < 3; ++axis) {
      std::iota(byAxis, byAxis + count, 0u);
      // Ties by position keep the order, and so the tree, the same from run to run.
      std::stable_sort(byAxis, byAxis + count, [&](uint32_t a, uint32_t b) {
        const Obb &boxA = boxes[a], &boxB = boxes[b];
        return boxA.lower[axis] + boxA.upper[axis] < boxB.lower[axis] + boxB.upper[axis];
      });
      Obb suffix = boxes[byAxis[count - 1]];
      for (uint32_t i = count - 1; i >= 1; --i) {
        suffix = unite(suffix, boxes[byAxis[i]]);
        suffixArea[i] = suffix.halfArea();
      }
      Obb prefix = boxes[byAxis[0]];
      for (uint32_t i = 1; i < count; ++i) {
        const float cost = nodeCost +
                           options_.intersectionCost *
                               (float(i) * prefix.halfArea() + float(count - i) * suffixArea[i]) / area;
        if (cost < bestCost) {
          bestCost = cost, bestAxis = axis, bestAt = i;
          std::copy(byAxis, byAxis + count, best);
        }
        prefix = unite(prefix, boxes[byAxis[i]]);
      }
    }
    if (bestAxis < 0) {
      if (mayBeLeaf) return makeLeaf();
      bestAt = count / 2;  // every box degenerate: any split
      std::iota(best, best + count, 0u);
    }
    permute(t.order.data() + begin, best, count);
    const uint32_t left = uint32_t(t.nodes.size());
    t.nodes.emplace_back();
    t.nodes.emplace_back();
    t.nodes[node].firstChildOrPrim = left;
    t.nodes[node].primCount = 0;
    split(t, left, begin, begin + bestAt, all.axis);
    split(t, left + 1, begin + bestAt, end, all.axis);
  }

  // values[i] = old values[order[i]].
  static void permute(uint32_t* values, const uint32_t* order, uint32_t count) {
    uint32_t old[kMaxTreeletTriangles];
    std::copy(values, values + count, old);
    for (uint32_t i = 0; i < count; ++i) values[i] = old[order[i]];
  }

  const StoredTriangle* triangles_;
  const BuildOptions& options_;
};

// True when every triangle lies in a plane of the world axes: the treelet's own frame is then the
// world's, in which the axis-aligned SAH chose its subtree already. Skipping them halved the time
// of this pass on mixed-654k; rebuilt as well, they changed the trees a little either way (leaf
// visits of hitting rays: small-1.5k 1.23 -> 1.18, diagonal-42k 2.28 -> 2.49).
bool allAxisAligned(const StoredTriangle* triangles, const uint32_t* prims, uint32_t count) {
  for (uint32_t i = 0; i < count; ++i) {
    const StoredTriangle& t = triangles[prims[i]];
    const Vec3f n = cross(t.v1 - t.v0, t.v2 - t.v0);
    if (int(n.x != 0.f) + int(n.y != 0.f) + int(n.z != 0.f) > 1) return false;
  }
  return true;
}

}  // namespace

void rebuildTreeletsInOwnFrames(BinaryBvh& bvh, const StoredTriangle* triangles, const BuildOptions& options) {
  if (bvh.empty()) return;
  // A subtree whose leaves are not contiguous in the leaf order (the builders' are) is left as it is.
  std::vector<uint32_t> preOrder;
  const std::vector<BinaryNodeInfo> info = binaryNodeInfos(bvh, preOrder);
  // Treelet roots: the highest nodes of at most kMaxTreeletTriangles contiguous triangles.
  std::vector<uint32_t> roots, stack = {0};
  while (!stack.empty()) {
    const uint32_t n = stack.back();
    stack.pop_back();
    const Bvh2Node& node = bvh.nodes[n];
    const bool contiguous = info[n].end - info[n].begin == info[n].primCount;
    if (info[n].primCount <= kMaxTreeletTriangles && contiguous && info[n].primCount >= 2) {
      roots.push_back(n);
      continue;
    }
    if (!node.isLeaf()) stack.insert(stack.end(), {node.firstChildOrPrim + 1, node.firstChildOrPrim});
  }
  std::vector<Treelet> treelets(roots.size());
  tbb::parallel_for(size_t(0), roots.size(), [&](size_t i) {
    const BinaryNodeInfo& r = info[roots[i]];
    if (allAxisAligned(triangles, bvh.primIndices.data() + r.begin, r.end - r.begin)) return;
    treelets[i] = TreeletBuilder(triangles, options).build(bvh.primIndices.data() + r.begin, r.end - r.begin);
  });
  // The new tree: the old nodes above the treelets, each treelet's nodes in place of its subtree.
  std::vector<int32_t> treeletOf(bvh.nodes.size(), -1);
  for (size_t i = 0; i < roots.size(); ++i) treeletOf[roots[i]] = int32_t(i);
  BinaryBvh out;
  out.primIndices = bvh.primIndices;
  out.nodes.reserve(bvh.nodes.size() + bvh.nodes.size() / 4);
  out.nodes.emplace_back();
  // (old node, new node) pairs to fill.
  std::vector<std::pair<uint32_t, uint32_t>> work = {{0u, 0u}};
  while (!work.empty()) {
    const auto [from, to] = work.back();
    work.pop_back();
    const Bvh2Node& node = bvh.nodes[from];
    if (treeletOf[from] >= 0 && !treelets[size_t(treeletOf[from])].nodes.empty()) {
      const Treelet& t = treelets[size_t(treeletOf[from])];
      const uint32_t base = info[from].begin;
      std::copy(t.order.begin(), t.order.end(), out.primIndices.begin() + base);
      // Treelet node k lands at index map[k] of the new tree.
      std::vector<uint32_t> map(t.nodes.size());
      map[0] = to;
      for (size_t k = 0; k < t.nodes.size(); ++k) {
        const Bvh2Node& tn = t.nodes[k];
        Bvh2Node& target = out.nodes[map[k]];
        target.bounds = tn.bounds;
        if (tn.isLeaf()) {
          target.firstChildOrPrim = base + tn.firstChildOrPrim;
          target.primCount = tn.primCount;
        } else {
          const uint32_t left = uint32_t(out.nodes.size());
          out.nodes.emplace_back();
          out.nodes.emplace_back();
          map[tn.firstChildOrPrim] = left;
          map[tn.firstChildOrPrim + 1] = left + 1;
          out.nodes[map[k]].firstChildOrPrim = left;
          out.nodes[map[k]].primCount = 0;
        }
      }
      continue;
    }
    out.nodes[to].bounds = node.bounds;
    out.nodes[to].primCount = node.primCount;
    if (node.isLeaf()) {
      out.nodes[to].firstChildOrPrim = node.firstChildOrPrim;
      continue;
    }
    const uint32_t left = uint32_t(out.nodes.size());
    out.nodes.emplace_back();
    out.nodes.emplace_back();
    out.nodes[to].firstChildOrPrim = left;
    work.push_back({node.firstChildOrPrim + 1, left + 1});
    work.push_back({node.firstChildOrPrim, left});
  }
  bvh = std::move(out);
}

}  // namespace obvh
