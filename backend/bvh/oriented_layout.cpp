#include "bvh/oriented_layout.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <array>
#include <limits>
#include <random>

#include "obb/obb.h"

namespace obvh {
namespace {

struct NodeInfo {
  uint32_t begin = 0, end = 0;  // triangle range in leaf order
  uint32_t parent = 0;
  int depth = 0;
};

std::vector<NodeInfo> nodeInfos(const BinaryBvh& bvh) {
  std::vector<NodeInfo> info(bvh.nodes.size());
  // Pre-order: children follow their parent, so one backwards pass fills interior ranges.
  std::vector<uint32_t> stack = {0};
  std::vector<uint32_t> order;
  order.reserve(bvh.nodes.size());
  while (!stack.empty()) {
    const uint32_t n = stack.back();
    stack.pop_back();
    order.push_back(n);
    const Bvh2Node& node = bvh.nodes[n];
    if (node.isLeaf()) {
      info[n].begin = node.firstChildOrPrim;
      info[n].end = node.firstChildOrPrim + node.primCount;
      continue;
    }
    for (uint32_t c : {node.firstChildOrPrim, node.firstChildOrPrim + 1}) {
      info[c].parent = n;
      info[c].depth = info[n].depth + 1;
      stack.push_back(c);
    }
  }
  for (auto it = order.rbegin(); it != order.rend(); ++it) {
    const Bvh2Node& node = bvh.nodes[*it];
    if (node.isLeaf()) continue;
    const NodeInfo &l = info[node.firstChildOrPrim], &r = info[node.firstChildOrPrim + 1];
    info[*it].begin = std::min(l.begin, r.begin);
    info[*it].end = std::max(l.end, r.end);
  }
  return info;
}

std::vector<Vec3f> pointsOf(const StoredTriangle* triangles, uint32_t begin, uint32_t end) {
  std::vector<Vec3f> points;
  points.reserve(3 * size_t(end - begin));
  for (uint32_t i = begin; i < end; ++i) points.insert(points.end(), {triangles[i].v0, triangles[i].v1, triangles[i].v2});
  return points;
}

float magnitudeOf(Vec3f lower, Vec3f upper) {
  float sum = 0.f;
  for (int k = 0; k < 3; ++k) {
    const float m = std::max(std::fabs(lower[k]), std::fabs(upper[k]));
    sum += m * m;
  }
  return std::sqrt(sum);
}

// k-means over leaf frames: features are the sign-free outer products of the longest two axes
// (orientation) and the box centre scaled by the scene size, so nearby leaves of one direction
// group together.
std::vector<int> kMeansOfFrames(const std::vector<Obb>& boxes, int k, float sceneSize) {
  const size_t n = boxes.size();
  constexpr int kDims = 15;
  std::vector<std::array<float, kDims>> features(n);
  for (size_t i = 0; i < n; ++i) {
    const Obb& b = boxes[i];
    int order[3] = {0, 1, 2};
    std::sort(order, order + 3, [&](int a, int c) { return b.upper[a] - b.lower[a] > b.upper[c] - b.lower[c]; });
    int f = 0;
    for (int which = 0; which < 2; ++which) {
      const Vec3f a = b.axis[order[which]];
      for (int r = 0; r < 3; ++r)
        for (int c = r; c < 3; ++c) features[i][size_t(f++)] = a[r] * a[c];
    }
    const Vec3f centre = (b.lower + b.upper) * 0.5f;  // in box coordinates; back to world:
    const Vec3f world = b.axis[0] * centre.x + b.axis[1] * centre.y + b.axis[2] * centre.z;
    for (int c = 0; c < 3; ++c) features[i][size_t(f++)] = 0.5f * world[c] / sceneSize;
  }
  k = int(std::min<size_t>(size_t(k), n));
  std::vector<std::array<float, kDims>> centres(static_cast<size_t>(k));
  std::mt19937 rng(12345);
  for (int c = 0; c < k; ++c) centres[size_t(c)] = features[(size_t(c) * n) / size_t(k)];
  std::vector<int> assignment(n, 0);
  for (int iteration = 0; iteration < 12; ++iteration) {
    tbb::parallel_for(size_t(0), n, [&](size_t i) {
      float best = std::numeric_limits<float>::infinity();
      for (int c = 0; c < k; ++c) {
        float d = 0.f;
        for (int j = 0; j < kDims; ++j) {
          const float e = features[i][size_t(j)] - centres[size_t(c)][size_t(j)];
          d += e * e;
        }
        if (d < best) best = d, assignment[i] = c;
      }
    });
    std::vector<std::array<double, kDims>> sums(static_cast<size_t>(k));
    std::vector<size_t> counts(static_cast<size_t>(k), 0);
    for (auto& s : sums) s.fill(0.0);
    for (size_t i = 0; i < n; ++i) {
      ++counts[size_t(assignment[i])];
      for (int j = 0; j < kDims; ++j) sums[size_t(assignment[i])][size_t(j)] += features[i][size_t(j)];
    }
    for (int c = 0; c < k; ++c) {
      if (counts[size_t(c)] == 0) {
        centres[size_t(c)] = features[rng() % n];  // re-seed an empty cluster
        continue;
      }
      for (int j = 0; j < kDims; ++j) centres[size_t(c)][size_t(j)] = float(sums[size_t(c)][size_t(j)] / double(counts[size_t(c)]));
    }
  }
  return assignment;
}

}  // namespace

OrientedBvh makeOrientedLayout(const BinaryBvh& binary, const StoredTriangle* triangles, const BuildOptions& options) {
  OrientedBvh out;
  if (binary.empty()) return out;
  const size_t n = binary.nodes.size();
  const std::vector<NodeInfo> info = nodeInfos(binary);
  std::vector<Obb> fitted(n);
  tbb::parallel_for(size_t(0), n, [&](size_t i) {
    const std::vector<Vec3f> points = pointsOf(triangles, info[i].begin, info[i].end);
    fitted[i] = fitDito14(points.data(), points.size());
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

  // Leaf clusters: the leaves that chose an oriented box share k frames.
  std::vector<int> clusterOf(n, -1);
  std::vector<Frame> clusterFrames;
  if (options.obbClusters > 0) {
    std::vector<size_t> leaves;
    std::vector<Obb> leafBoxes;
    for (size_t i = 0; i < n; ++i)
      if (binary.nodes[i].isLeaf() && oriented[i]) leaves.push_back(i), leafBoxes.push_back(fitted[i]);
    if (!leaves.empty()) {
      const Box3f& root = binary.nodes[0].bounds;
      const float sceneSize = std::max(magnitudeOf(root.upper - root.lower, {0.f, 0.f, 0.f}), 1e-30f);
      const std::vector<int> assignment = kMeansOfFrames(leafBoxes, options.obbClusters, sceneSize);
      // Each cluster's frame: that of its member with the largest box (it covers the most area).
      std::vector<int> representative(size_t(options.obbClusters), -1);
      for (size_t j = 0; j < leaves.size(); ++j) {
        int& r = representative[size_t(assignment[j])];
        if (r < 0 || leafBoxes[j].halfArea() > leafBoxes[size_t(r)].halfArea()) r = int(j);
      }
      std::vector<int> frameOfCluster(size_t(options.obbClusters), -1);
      for (size_t c = 0; c < representative.size(); ++c)
        if (representative[c] >= 0) {
          frameOfCluster[c] = int(clusterFrames.size());
          const Obb& b = leafBoxes[size_t(representative[c])];
          clusterFrames.push_back({{b.axis[0], b.axis[1], b.axis[2]}});
        }
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
