#include "builders/obb_split_builder.h"

#include <tbb/parallel_invoke.h>

#include <algorithm>
#include <limits>
#include <memory>

#include "obb/obb.h"

namespace obvh {
namespace {

constexpr size_t kParallelThreshold = 1 << 12;
constexpr int kMaxDepth = 64;  // past it: object median, which bounds the depth for the traversal stacks

struct FramedPrim {
  Box3f box;       // the primitive's bounds in the node's frame
  float centroid;  // centroid along the split axis, in the node's frame
};

struct TempNode {
  Box3f bounds;
  size_t begin = 0, end = 0;
  std::unique_ptr<TempNode> left, right;
};

class ObbFrameBuilder {
 public:
  ObbFrameBuilder(PrimRefs& refs, const StoredTriangle* triangles, const BuildOptions& options)
      : refs_(refs), triangles_(triangles), options_(options) {}

  std::unique_ptr<TempNode> build(size_t begin, size_t end, int depth) {
    auto node = std::make_unique<TempNode>();
    node->begin = begin, node->end = end;
    for (size_t i = begin; i < end; ++i) node->bounds.extend(refs_[i].bounds);
    const size_t count = end - begin;
    if (count <= 1) return node;
    const size_t middle = split(begin, end, depth, count <= size_t(options_.maxLeafSize));
    if (middle == begin || middle == end) return node;  // a leaf
    auto buildLeft = [&] { node->left = build(begin, middle, depth + 1); };
    auto buildRight = [&] { node->right = build(middle, end, depth + 1); };
    if (count >= kParallelThreshold) {
      tbb::parallel_invoke(buildLeft, buildRight);
    } else {
      buildLeft();
      buildRight();
    }
    return node;
  }

 private:
  const StoredTriangle& triangle(size_t i) const { return triangles_[refs_[i].index]; }

  Vec3f centroid(size_t i) const { return centroidOf(refs_[i]); }

  // Returns the partition point, or begin when the range should stay a leaf.
  size_t split(size_t begin, size_t end, int depth, bool mayStayLeaf) {
    const size_t count = end - begin;
    std::vector<Vec3f> points;
    points.reserve(3 * count);
    for (size_t i = begin; i < end; ++i) {
      const StoredTriangle& t = triangle(i);
      points.insert(points.end(), {t.v0, t.v1, t.v2});
    }
    const Obb frame = fitObb(options_.obbFit, points.data(), points.size());
    // Centroid extent per frame axis decides the axis for midpoint and median splits.
    Box3f centroids;
    for (size_t i = begin; i < end; ++i) centroids.extend(frame.toBoxFrame(centroid(i)));
    const int axis = centroids.largestAxis();
    if (!(centroids.upper[axis] > centroids.lower[axis])) return mayStayLeaf ? begin : begin + count / 2;

    ObbSplit mode = options_.obbSplit;
    if (depth >= kMaxDepth) mode = ObbSplit::Median;
    if (mode == ObbSplit::Sah) return splitSah(begin, end, frame, centroids, mayStayLeaf);
    if (mode == ObbSplit::Midpoint) {
      if (mayStayLeaf) return begin;
      const float mid = 0.5f * (centroids.lower[axis] + centroids.upper[axis]);
      const auto it = std::partition(refs_.begin() + long(begin), refs_.begin() + long(end),
                                     [&](const PrimRef& r) { return frame.toBoxFrame(centroidOf(r))[axis] < mid; });
      const size_t middle = size_t(it - refs_.begin());
      if (middle != begin && middle != end) return middle;
    }
    if (mayStayLeaf) return begin;
    const size_t middle = begin + count / 2;
    std::nth_element(refs_.begin() + long(begin), refs_.begin() + long(middle), refs_.begin() + long(end),
                     [&](const PrimRef& a, const PrimRef& b) {
                       return frame.toBoxFrame(centroidOf(a))[axis] < frame.toBoxFrame(centroidOf(b))[axis];
                     });
    return middle;
  }

  Vec3f centroidOf(const PrimRef& r) const {
    const StoredTriangle& t = triangles_[r.index];
    return (t.v0 + t.v1 + t.v2) * (1.f / 3.f);
  }

  // Binned SAH over boxes in the node's frame, on each of its three axes.
  size_t splitSah(size_t begin, size_t end, const Obb& frame, const Box3f& centroids, bool mayStayLeaf) {
    const size_t count = end - begin;
    const int binCount = std::max(2, std::min(options_.obbBins, int(count) * 2));
    std::vector<Box3f> framed(count);
    std::vector<Vec3f> framedCentroid(count);
    for (size_t i = 0; i < count; ++i) {
      const StoredTriangle& t = triangle(begin + i);
      framed[i].extend(frame.toBoxFrame(t.v0));
      framed[i].extend(frame.toBoxFrame(t.v1));
      framed[i].extend(frame.toBoxFrame(t.v2));
      framedCentroid[i] = frame.toBoxFrame(centroid(begin + i));
    }
    Box3f whole;
    for (const Box3f& b : framed) whole.extend(b);
    float bestCost = std::numeric_limits<float>::infinity();
    int bestAxis = -1, bestBin = 0;
    const size_t bins = size_t(binCount);
    std::vector<Box3f> binBounds(bins);
    std::vector<uint32_t> binCounts(bins);
    std::vector<float> rightArea(bins);
    std::vector<uint32_t> rightCount(bins);
    auto binOf = [&](int axis, float c) {
      const float extent = centroids.upper[axis] - centroids.lower[axis];
      const int b = int(float(binCount) * (c - centroids.lower[axis]) / extent);
      return std::min(std::max(b, 0), binCount - 1);
    };
    for (int axis = 0; axis < 3; ++axis) {
      if (!(centroids.upper[axis] > centroids.lower[axis])) continue;
      std::fill(binBounds.begin(), binBounds.end(), Box3f{});
      std::fill(binCounts.begin(), binCounts.end(), 0u);
      for (size_t i = 0; i < count; ++i) {
        const int b = binOf(axis, framedCentroid[i][axis]);
        binBounds[size_t(b)].extend(framed[i]);
        ++binCounts[size_t(b)];
      }
      Box3f acc;
      uint32_t n = 0;
      for (int b = binCount - 1; b > 0; --b) {
        acc.extend(binBounds[size_t(b)]);
        n += binCounts[size_t(b)];
        rightArea[size_t(b)] = acc.halfArea();
        rightCount[size_t(b)] = n;
      }
      acc = Box3f{};
      n = 0;
      for (int b = 1; b < binCount; ++b) {  // split between bin b-1 and bin b
        acc.extend(binBounds[size_t(b - 1)]);
        n += binCounts[size_t(b - 1)];
        if (n == 0 || rightCount[size_t(b)] == 0) continue;
        const float cost = acc.halfArea() * float(n) + rightArea[size_t(b)] * float(rightCount[size_t(b)]);
        if (cost < bestCost) bestCost = cost, bestAxis = axis, bestBin = b;
      }
    }
    const float parentArea = std::max(whole.halfArea(), 1e-30f);
    const float splitCost = options_.traversalCost + options_.intersectionCost * bestCost / parentArea;
    const float leafCost = options_.intersectionCost * float(count);
    if (mayStayLeaf && (bestAxis < 0 || leafCost <= splitCost)) return begin;
    if (bestAxis < 0) return medianSplit(begin, end, frame, centroids);
    // Partition by the same bin arithmetic as the binning.
    size_t left = begin;
    PrimRefs right;
    right.reserve(count);
    for (size_t i = 0; i < count; ++i) {
      const PrimRef r = refs_[begin + i];
      if (binOf(bestAxis, framedCentroid[i][bestAxis]) < bestBin) refs_[left++] = r;
      else right.push_back(r);
    }
    std::copy(right.begin(), right.end(), refs_.begin() + long(left));
    return left;
  }

  size_t medianSplit(size_t begin, size_t end, const Obb& frame, const Box3f& centroids) {
    const int axis = centroids.largestAxis();
    const size_t middle = begin + (end - begin) / 2;
    std::nth_element(refs_.begin() + long(begin), refs_.begin() + long(middle), refs_.begin() + long(end),
                     [&](const PrimRef& a, const PrimRef& b) {
                       return frame.toBoxFrame(centroidOf(a))[axis] < frame.toBoxFrame(centroidOf(b))[axis];
                     });
    return middle;
  }

  PrimRefs& refs_;
  const StoredTriangle* triangles_;
  const BuildOptions& options_;
};

void flatten(const TempNode& node, uint32_t index, BinaryBvh& out) {
  out.nodes[index].bounds = node.bounds;
  if (!node.left) {
    out.nodes[index].firstChildOrPrim = uint32_t(node.begin);
    out.nodes[index].primCount = uint32_t(node.end - node.begin);
    return;
  }
  const uint32_t left = uint32_t(out.nodes.size());
  out.nodes.resize(out.nodes.size() + 2);
  out.nodes[index].firstChildOrPrim = left;
  out.nodes[index].primCount = 0;
  flatten(*node.left, left, out);
  flatten(*node.right, left + 1, out);
}

}  // namespace

BinaryBvh buildInObbFrames(PrimRefs& refs, const StoredTriangle* triangles, const BuildOptions& options) {
  BinaryBvh bvh;
  if (refs.empty()) return bvh;
  ObbFrameBuilder builder(refs, triangles, options);
  const std::unique_ptr<TempNode> root = builder.build(0, refs.size(), 0);
  bvh.nodes.resize(1);
  flatten(*root, 0, bvh);
  bvh.primIndices.resize(refs.size());
  for (size_t i = 0; i < refs.size(); ++i) bvh.primIndices[i] = refs[i].index;
  return bvh;
}

}  // namespace obvh
