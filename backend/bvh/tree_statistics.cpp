#include "bvh/tree_statistics.h"

#include <cmath>

namespace obvh {
namespace {

// Sum over the subtree below child code `child` whose box is `box`, in units of area.
template <int N>
double areaWeightedCost(const WideBvh<N>& bvh, uint32_t child, const Box3f& box) {
  if (WideNode<N>::isLeaf(child)) return double(box.halfArea()) * WideNode<N>::leafBlockCount(child);
  const WideNode<N>& node = bvh.nodes[child];
  double cost = box.halfArea();
  for (int lane = 0; lane < N; ++lane)
    if (node.child[lane] != WideNode<N>::kEmptyChild) cost += areaWeightedCost(bvh, node.child[lane], node.childBox(lane));
  return cost;
}

double areaWeightedCost(const BinaryBvh& bvh, uint32_t index) {
  const Bvh2Node& node = bvh.nodes[index];
  if (node.isLeaf()) return double(node.bounds.halfArea()) * double((node.primCount + 3) / 4);
  return double(node.bounds.halfArea()) + areaWeightedCost(bvh, node.firstChildOrPrim) +
         areaWeightedCost(bvh, node.firstChildOrPrim + 1);
}

}  // namespace

template <int N>
double statisticsSah(const WideBvh<N>& bvh) {
  if (bvh.empty()) return 0.0;
  if (WideNode<N>::isLeaf(bvh.rootChild)) {
    // A single leaf: its own box is the root's, so it counts its blocks.
    return double(WideNode<N>::leafBlockCount(bvh.rootChild));
  }
  const Box3f root = bvh.rootNodeBox();
  const double area = root.halfArea();
  return area > 0.0 ? areaWeightedCost(bvh, bvh.rootChild, root) / area : 0.0;
}

double statisticsSah(const BinaryBvh& bvh) {
  if (bvh.empty()) return 0.0;
  const double area = bvh.nodes[0].bounds.halfArea();
  if (bvh.nodes[0].isLeaf()) return double((bvh.nodes[0].primCount + 3) / 4);
  return area > 0.0 ? areaWeightedCost(bvh, 0) / area : 0.0;
}

template double statisticsSah<4>(const WideBvh<4>&);
template double statisticsSah<8>(const WideBvh<8>&);

}  // namespace obvh
