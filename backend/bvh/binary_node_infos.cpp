#include "bvh/binary_node_infos.h"

#include <algorithm>

namespace obvh {

std::vector<BinaryNodeInfo> binaryNodeInfos(const BinaryBvh& bvh, std::vector<uint32_t>& preOrder) {
  std::vector<BinaryNodeInfo> info(bvh.nodes.size());
  preOrder.clear();
  if (bvh.empty()) return info;
  preOrder.reserve(bvh.nodes.size());
  // Pre-order: children follow their parent, so one backwards pass fills interior ranges.
  std::vector<uint32_t> stack = {0};
  while (!stack.empty()) {
    const uint32_t n = stack.back();
    stack.pop_back();
    preOrder.push_back(n);
    const Bvh2Node& node = bvh.nodes[n];
    if (node.isLeaf()) {
      info[n].begin = node.firstChildOrPrim;
      info[n].end = node.firstChildOrPrim + node.primCount;
      info[n].primCount = node.primCount;
      continue;
    }
    for (uint32_t c : {node.firstChildOrPrim, node.firstChildOrPrim + 1}) {
      info[c].parent = n;
      info[c].depth = info[n].depth + 1;
      stack.push_back(c);
    }
  }
  for (auto it = preOrder.rbegin(); it != preOrder.rend(); ++it) {
    const Bvh2Node& node = bvh.nodes[*it];
    if (node.isLeaf()) continue;
    const BinaryNodeInfo &l = info[node.firstChildOrPrim], &r = info[node.firstChildOrPrim + 1];
    info[*it].begin = std::min(l.begin, r.begin);
    info[*it].end = std::max(l.end, r.end);
    info[*it].primCount = l.primCount + r.primCount;
  }
  return info;
}

}  // namespace obvh
