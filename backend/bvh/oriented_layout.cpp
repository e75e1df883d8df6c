#include "bvh/oriented_layout.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "bvh/binary_node_infos.h"
#include "bvh/frame_clustering.h"
#include "obb/obb.h"

namespace obvh {
namespace {

using NodeInfo = BinaryNodeInfo;

std::vector<Vec3f> pointsOf(const StoredTriangle* triangles, uint32_t begin, uint32_t end) {
  std::vector<Vec3f> points;
  points.reserve(3 * size_t(end - begin));
  for (uint32_t i = begin; i < end; ++i) points.insert(points.end(), {triangles[i].v0, triangles[i].v1, triangles[i].v2});
  return points;
}

// Every node's box in one frame: the leaves refitted, each interior node the union of its
// children's boxes, children first. The same float box as a refit over the node's own points, since
// rounding outwards (fitWithAxes) is monotonic, for the cost of one refit of the leaves.
std::vector<Obb> boxesInFrame(const Frame& frame, const BinaryBvh& binary, const std::vector<NodeInfo>& info,
                              const std::vector<uint32_t>& preOrder, const StoredTriangle* triangles) {
  std::vector<Obb> boxes(binary.nodes.size());
  tbb::parallel_for(size_t(0), boxes.size(), [&](size_t i) {
    if (!binary.nodes[i].isLeaf()) return;
    const std::vector<Vec3f> points = pointsOf(triangles, info[i].begin, info[i].end);
    boxes[i] = fitWithAxes(frame.axis, points.data(), points.size());
  });
  for (auto it = preOrder.rbegin(); it != preOrder.rend(); ++it) {
    const Bvh2Node& node = binary.nodes[*it];
    if (node.isLeaf()) continue;
    const Obb &l = boxes[node.firstChildOrPrim], &r = boxes[node.firstChildOrPrim + 1];
    Obb& box = boxes[*it];
    for (int k = 0; k < 3; ++k) box.axis[k] = frame.axis[k];
    box.lower = {std::min(l.lower.x, r.lower.x), std::min(l.lower.y, r.lower.y), std::min(l.lower.z, r.lower.z)};
    box.upper = {std::max(l.upper.x, r.upper.x), std::max(l.upper.y, r.upper.y), std::max(l.upper.z, r.upper.z)};
  }
  return boxes;
}

float magnitudeOf(Vec3f lower, Vec3f upper) {
  float sum = 0.f;
  for (int k = 0; k < 3; ++k) {
    const float m = std::max(std::fabs(lower[k]), std::fabs(upper[k]));
    sum += m * m;
  }
  return std::sqrt(sum);
}

// The nodes that pass `keep`, ordered by their triangle ranges in leaf order: the parallel
// builders number the nodes of one tree differently from run to run, and k-means seeds from the
// order it is given.
template <typename Keep>
std::vector<size_t> inTreeOrder(const std::vector<NodeInfo>& info, Keep&& keep) {
  std::vector<size_t> nodes;
  for (size_t i = 0; i < info.size(); ++i)
    if (keep(i)) nodes.push_back(i);
  std::sort(nodes.begin(), nodes.end(), [&](size_t a, size_t b) {
    return info[a].begin != info[b].begin ? info[a].begin < info[b].begin : info[a].end > info[b].end;
  });
  return nodes;
}

// How much larger than its own oriented box a node's box may grow in a palette frame. Measured on
// the stack presets (SAH cost, obb_palette=7): 1.0 left more nodes on the per-child transform and
// cost more (small-1.5k 118.4 against 109.6); 1.05-1.25 were alike; unbounded, mixed-654k's SAH
// cost doubled (3,191 -> 7,313), its vias and stepped walls fitting no palette frame.
constexpr float kPaletteSlack = 1.1f;
// Oriented boxes the palette's k-means looks at, at most (mixed-654k has 293k: k-means over all of
// them took about a third of the build).
constexpr size_t kPaletteSample = 16384;
}  // namespace

OrientedBvh makeOrientedLayout(const BinaryBvh& binary, const StoredTriangle* triangles, const BuildOptions& options) {
  OrientedBvh out;
  if (binary.empty()) return out;
  const size_t n = binary.nodes.size();
  std::vector<uint32_t> preOrder;
  const std::vector<NodeInfo> info = binaryNodeInfos(binary, preOrder);
  std::vector<Obb> fitted(n);
  tbb::parallel_for(size_t(0), n, [&](size_t i) {
    const std::vector<Vec3f> points = pointsOf(triangles, info[i].begin, info[i].end);
    fitted[i] = fitObb(options.obbFit, points.data(), points.size());
  });
  auto aabbArea = [&](size_t i) { return binary.nodes[i].bounds.halfArea(); };
  std::vector<uint8_t> oriented(n, 0);
  if (options.layout == AccelLayout::Hybrid) {
    // Children before parents (reverse pre-order): the cost of testing a node's children is known
    // when the node decides. A node pays its own test with the probability of reaching its parent
    // (the parent's smaller area) and the tests below it with the probability of entering it.
    std::vector<float> childTests(n, 0.f);
    for (size_t idx = n; idx-- > 0;) {
      const Bvh2Node& node = binary.nodes[idx];
      const float below = node.isLeaf() ? options.intersectionCost * float(node.primCount) : childTests[idx];
      const size_t parent = idx == 0 ? 0 : info[idx].parent;
      const float reach = std::min(aabbArea(parent), fitted[parent].halfArea());
      const float aabbCost = options.traversalCost * reach + aabbArea(idx) * below;
      const float obbCost = options.traversalCost * options.obbTestCost * reach + fitted[idx].halfArea() * below;
      oriented[idx] = obbCost < aabbCost;
      if (idx != 0) childTests[parent] += options.traversalCost * (oriented[idx] ? options.obbTestCost : 1.f);
    }
  } else {
    for (size_t i = 0; i < n; ++i) oriented[i] = fitted[i].halfArea() < aabbArea(i);
  }

  // Leaf clusters: the leaves that chose an oriented box share k frames. A palette: an oriented
  // node takes the best of a few frames shared by the whole tree where its box fits in it about as
  // tightly as in its own (clusters are then moot).
  std::vector<int> clusterOf(n, -1);
  std::vector<Frame> clusterFrames;
  if (options.obbPalette > 0) {
    const std::vector<size_t> members = inTreeOrder(info, [&](size_t i) { return oriented[i] != 0; });
    // A few frames need no more than a sample to be found: every stride-th box in tree order.
    const size_t stride = std::max<size_t>(1, members.size() / kPaletteSample);
    std::vector<Obb> boxes;
    std::vector<Features> features;
    for (size_t j = 0; j < members.size(); j += stride)
      boxes.push_back(fitted[members[j]]), features.push_back(orientationFeatures(fitted[members[j]]));
    if (!members.empty()) {
      const int k = std::min(options.obbPalette, kMaxPaletteFrames);
      std::vector<int> frameOfCluster;
      Obb identity;
      const Features axisAligned = orientationFeatures(identity);
      const std::vector<int> assignment = kMeans(features, k, &axisAligned);
      // Cluster 0 is the identity's, which the palette holds anyway: its members drop out.
      std::vector<Obb> framedBoxes;
      std::vector<Features> framedFeatures;
      std::vector<int> framedAssignment;
      for (size_t j = 0; j < boxes.size(); ++j)
        if (assignment[j] > 0)
          framedBoxes.push_back(boxes[j]), framedFeatures.push_back(features[j]), framedAssignment.push_back(assignment[j] - 1);
      representativeFrames(framedBoxes, framedFeatures, framedAssignment, k, Representative::NearestMean, clusterFrames,
                           frameOfCluster);
      std::vector<float> bestArea(members.size());
      std::vector<Obb> best(members.size());
      for (size_t j = 0; j < members.size(); ++j) bestArea[j] = aabbArea(members[j]);
      for (size_t f = 0; f < clusterFrames.size(); ++f) {
        const std::vector<Obb> inFrame = boxesInFrame(clusterFrames[f], binary, info, preOrder, triangles);
        for (size_t j = 0; j < members.size(); ++j)
          if (inFrame[members[j]].halfArea() < bestArea[j])
            bestArea[j] = inFrame[members[j]].halfArea(), best[j] = inFrame[members[j]], clusterOf[members[j]] = int(f);
      }
      for (size_t j = 0; j < members.size(); ++j) {
        const size_t node = members[j];
        if (bestArea[j] <= kPaletteSlack * fitted[node].halfArea()) {
          if (clusterOf[node] < 0) oriented[node] = 0;  // the axis-aligned box (the identity's slot)
          else fitted[node] = best[j];
        } else {
          clusterOf[node] = -1;  // keeps its own frame
        }
      }
    }
    out.paletteFrames = uint32_t(clusterFrames.size());
  } else if (options.obbClusters > 0) {
    const std::vector<size_t> leaves =
        inTreeOrder(info, [&](size_t i) { return binary.nodes[i].isLeaf() && oriented[i]; });
    std::vector<Obb> leafBoxes;
    for (size_t i : leaves) leafBoxes.push_back(fitted[i]);
    if (!leaves.empty()) {
      const Box3f& root = binary.nodes[0].bounds;
      const float sceneSize = std::max(magnitudeOf(root.upper - root.lower, {0.f, 0.f, 0.f}), 1e-30f);
      std::vector<Features> features(leaves.size());
      for (size_t j = 0; j < leaves.size(); ++j) features[j] = leafClusterFeatures(leafBoxes[j], sceneSize);
      const std::vector<int> assignment = kMeans(features, options.obbClusters);
      std::vector<int> frameOfCluster;
      representativeFrames(leafBoxes, features, assignment, options.obbClusters, Representative::LargestBox, clusterFrames,
                           frameOfCluster);
      tbb::parallel_for(size_t(0), leaves.size(), [&](size_t j) {
        const size_t node = leaves[j];
        const Frame& frame = clusterFrames[size_t(frameOfCluster[size_t(assignment[j])])];
        const std::vector<Vec3f> points = pointsOf(triangles, info[node].begin, info[node].end);
        const Obb refit = fitWithAxes(frame.axis, points.data(), points.size());
        if (refit.halfArea() < aabbArea(node)) {
          fitted[node] = refit;
          clusterOf[node] = frameOfCluster[size_t(assignment[j])];
        } else {
          oriented[node] = 0;
        }
      });
    }
  }
  out.frames = clusterFrames;

  out.nodes.resize(n);
  for (size_t i = 0; i < n; ++i) {
    OrientedNode& node = out.nodes[i];
    const Bvh2Node& source = binary.nodes[i];
    node.firstChildOrPrim = source.firstChildOrPrim;
    node.primCount = source.primCount;
    if (oriented[i]) {
      node.lower = fitted[i].lower, node.upper = fitted[i].upper;
      if (clusterOf[i] >= 0) {
        node.frame = uint32_t(clusterOf[i]);
      } else {
        node.frame = uint32_t(out.frames.size());
        out.frames.push_back({{fitted[i].axis[0], fitted[i].axis[1], fitted[i].axis[2]}});
      }
    } else {
      node.lower = source.bounds.lower, node.upper = source.bounds.upper;
    }
    node.magnitude = magnitudeOf(node.lower, node.upper);
  }
  return out;
}

namespace {

template <typename Tree, typename AreaOf, typename TestCostOf>
LayoutMetrics measure(const Tree& nodes, AreaOf&& area, TestCostOf&& testCost, const BuildOptions& options) {
  LayoutMetrics m;
  if (nodes.empty()) return m;
  const double rootArea = std::max(double(area(0)), 1e-300);
  m.sahCost = testCost(0);
  std::vector<std::pair<uint32_t, int>> stack = {{0, 0}};
  std::vector<int> leafDepths;
  while (!stack.empty()) {
    const auto [index, depth] = stack.back();
    stack.pop_back();
    const auto& node = nodes[index];
    ++m.nodeCount;
    const double p = double(area(index)) / rootArea;
    if (node.isLeaf()) {
      ++m.leafCount;
      leafDepths.push_back(depth);
      m.sahCost += p * options.intersectionCost * node.primCount;
      continue;
    }
    const uint32_t l = node.firstChildOrPrim;
    m.sahCost += p * (testCost(l) + testCost(l + 1));
    stack.push_back({l, depth + 1});
    stack.push_back({l + 1, depth + 1});
  }
  double sum = 0, sumSq = 0;
  for (int d : leafDepths) sum += d, sumSq += double(d) * d;
  m.meanLeafDepth = sum / double(leafDepths.size());
  m.depthStdDev = std::sqrt(std::max(0.0, sumSq / double(leafDepths.size()) - m.meanLeafDepth * m.meanLeafDepth));
  return m;
}

}  // namespace

LayoutMetrics measureLayout(const OrientedBvh& bvh, const BuildOptions& options) {
  LayoutMetrics m = measure(
      bvh.nodes,
      [&](uint32_t i) {
        const OrientedNode& n = bvh.nodes[i];
        const Vec3f d = n.upper - n.lower;
        return d.x * d.y + d.y * d.z + d.z * d.x;
      },
      [&](uint32_t i) { return options.traversalCost * (bvh.nodes[i].oriented() ? options.obbTestCost : 1.f); },
      options);
  for (const OrientedNode& n : bvh.nodes) m.orientedNodeCount += n.oriented();
  m.frameCount = bvh.frames.size();
  m.memoryBytes = bvh.nodes.size() * sizeof(OrientedNode) + bvh.frames.size() * sizeof(Frame);
  return m;
}

LayoutMetrics measureLayout(const BinaryBvh& bvh, const BuildOptions& options) {
  LayoutMetrics m = measure(
      bvh.nodes, [&](uint32_t i) { return bvh.nodes[i].bounds.halfArea(); },
      [&](uint32_t) { return options.traversalCost; }, options);
  m.memoryBytes = bvh.nodes.size() * sizeof(Bvh2Node);
  return m;
}

}  // namespace obvh
