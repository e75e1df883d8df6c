#include "builders/kmeans_builder.h"

#include <tbb/parallel_invoke.h>

#include <algorithm>
#include <array>
#include <cstdint>
#include <limits>

#include "builders/binary_node_storage.h"
#include "builders/deterministic_reduce.h"
#include "builders/object_median.h"

namespace obvh {
namespace {

constexpr int kMaxArity = 8;
constexpr int kMaxIterations = 8;
constexpr size_t kParallelRecursionThreshold = 1 << 12;
// Past this depth nodes split at the object median, which bounds the tree's depth (fixed-size
// traversal stacks) even when clustering keeps peeling off a few outliers.
constexpr int kMedianSplitDepth = 40;

struct ClusterSums {
  std::array<double, 3 * kMaxArity> sum{};
  std::array<size_t, kMaxArity> count{};
  void merge(const ClusterSums& o) {
    for (size_t i = 0; i < sum.size(); ++i) sum[i] += o.sum[i];
    for (size_t i = 0; i < count.size(); ++i) count[i] += o.count[i];
  }
};

struct ChangeCount {
  size_t changed = 0;
  void merge(const ChangeCount& o) { changed += o.changed; }
};

struct CentroidBounds {
  Box3f box;
  void merge(const CentroidBounds& o) { box.extend(o.box); }
};

class KMeansBuilder {
 public:
  KMeansBuilder(PrimRefs& refs, const BuildOptions& options, BinaryBvh& out)
      : refs_(refs),
        maxLeaf_(size_t(std::max(options.maxLeafSize, 1))),
        arity_(std::clamp(options.kmeansArity, 2, kMaxArity)),
        out_(out),
        cluster_(refs.size()),
        scratch_(refs.size()) {}

  void run() {
    buildIntoBinaryBvh(refs_, out_, [&](BinaryNodeStorage& nodes) {
      nodes_ = &nodes;
      build(0, 0, refs_.size(), 0);
      nodes_ = nullptr;
    });
  }

 private:
  struct Range {
    size_t begin, end;
    float key;  // the cluster centre along the node's widest axis: orders the clusters
  };

  Box3f build(uint32_t nodeIndex, size_t begin, size_t end, int depth) {
    const size_t n = end - begin;
    if (n <= maxLeaf_) {
      Bvh2Node& node = nodes_->make(nodeIndex);
      Box3f box;
      for (size_t i = begin; i < end; ++i) box.extend(refs_[i].bounds);
      node.bounds = box;
      node.firstChildOrPrim = uint32_t(begin);
      node.primCount = uint32_t(n);
      return box;
    }
    const int k = int(std::min<size_t>(size_t(arity_), (n + maxLeaf_ - 1) / maxLeaf_));
    std::vector<Range> ranges = depth < kMedianSplitDepth ? cluster(begin, end, std::max(k, 2)) : std::vector<Range>{};
    if (ranges.size() < 2) ranges = medianHalves(begin, end);
    return buildGroup(nodeIndex, ranges.data(), ranges.size(), depth);
  }

  // The clusters ranges[0..count) under nodeIndex: halves of the list (ordered along the widest
  // axis) become the two children until one cluster is left.
  Box3f buildGroup(uint32_t nodeIndex, const Range* ranges, size_t count, int depth) {
    if (count == 1) return build(nodeIndex, ranges[0].begin, ranges[0].end, depth + 1);
    const size_t half = count / 2;
    const uint32_t left = nodes_->claimPair();
    Box3f leftBox, rightBox;
    const size_t size = ranges[count - 1].end - ranges[0].begin;
    const auto buildLeft = [&] { leftBox = buildGroup(left, ranges, half, depth + 1); };
    const auto buildRight = [&] { rightBox = buildGroup(left + 1, ranges + half, count - half, depth + 1); };
    if (size > kParallelRecursionThreshold) {
      tbb::parallel_invoke(buildLeft, buildRight);
    } else {
      buildLeft();
      buildRight();
    }
    Bvh2Node& node = nodes_->make(nodeIndex);  // made once its children are built
    node.firstChildOrPrim = left;
    node.primCount = 0;
    node.bounds = leftBox;
    node.bounds.extend(rightBox);
    return node.bounds;
  }

  // Lloyd's algorithm on the centroids of refs[begin, end): k starting centres are the means of
  // k equal slabs along the widest axis; at most kMaxIterations rounds, fewer once no primitive
  // changes cluster. Reorders the range by cluster; returns the non-empty clusters in order.
  std::vector<Range> cluster(size_t begin, size_t end, int k) {
    const Box3f centroids = reduceDeterministically<CentroidBounds>(begin, end, [&](size_t b, size_t e, CentroidBounds& acc) {
                              for (size_t i = b; i < e; ++i) acc.box.extend(refs_[i].bounds.center2());
                            }).box;
    const int axis = centroids.largestAxis();
    const float lo = centroids.lower[axis], extent = centroids.upper[axis] - lo;
    if (!(extent > 0.f)) return {};
    const float slabScale = float(k) / extent;
    for (size_t i = begin; i < end; ++i) {
      const float t = (refs_[i].bounds.center2()[axis] - lo) * slabScale;
      cluster_[i] = uint8_t(std::clamp(int(t), 0, k - 1));
    }
    std::array<Vec3f, kMaxArity> centre{};
    for (int iteration = 0; iteration < kMaxIterations; ++iteration) {
      const ClusterSums sums = reduceDeterministically<ClusterSums>(begin, end, [&](size_t b, size_t e, ClusterSums& acc) {
        for (size_t i = b; i < e; ++i) {
          const Vec3f c = refs_[i].bounds.center2();
          const int id = cluster_[i];
          acc.sum[3 * id] += c.x, acc.sum[3 * id + 1] += c.y, acc.sum[3 * id + 2] += c.z;
          ++acc.count[id];
        }
      });
      // Emptied clusters are dropped: remap[id] is the cluster's index among the remaining centres.
      std::array<int, kMaxArity> remap{};
      int centres = 0;
      for (int id = 0; id < k; ++id) {
        if (sums.count[id] == 0) continue;
        const double inv = 1.0 / double(sums.count[id]);
        remap[id] = centres;
        centre[centres++] = {float(sums.sum[3 * id] * inv), float(sums.sum[3 * id + 1] * inv), float(sums.sum[3 * id + 2] * inv)};
      }
      const size_t changed = reduceDeterministically<ChangeCount>(begin, end, [&](size_t b, size_t e, ChangeCount& acc) {
                               for (size_t i = b; i < e; ++i) {
                                 const Vec3f c = refs_[i].bounds.center2();
                                 int best = 0;
                                 float bestDistance = std::numeric_limits<float>::infinity();
                                 for (int id = 0; id < centres; ++id) {
                                   const Vec3f d = c - centre[id];
                                   const float distance = d.x * d.x + d.y * d.y + d.z * d.z;
                                   if (distance < bestDistance) bestDistance = distance, best = id;
                                 }
                                 acc.changed += remap[cluster_[i]] != best;
                                 cluster_[i] = uint8_t(best);
                               }
                             }).changed;
      k = centres;
      if (changed == 0) break;
    }
    return groupByCluster(begin, end, k, axis);
  }

  std::vector<Range> groupByCluster(size_t begin, size_t end, int k, int axis) {
    std::array<size_t, kMaxArity + 1> start{};
    std::array<double, kMaxArity> keySum{};
    for (size_t i = begin; i < end; ++i) {
      ++start[cluster_[i] + 1];
      keySum[cluster_[i]] += refs_[i].bounds.center2()[axis];
    }
    std::vector<Range> ranges;
    for (int id = 0; id < k; ++id) {
      if (start[id + 1] > 0)
        ranges.push_back({begin + start[id], begin + start[id] + start[id + 1], float(keySum[id] / double(start[id + 1]))});
      start[id + 1] += start[id];
    }
    if (ranges.size() < 2) return {};
    // A stable counting sort keeps the primitives' relative order inside each cluster.
    std::array<size_t, kMaxArity + 1> next = start;
    for (size_t i = begin; i < end; ++i) scratch_[begin + next[cluster_[i]]++] = refs_[i];
    std::copy(scratch_.begin() + long(begin), scratch_.begin() + long(end), refs_.begin() + long(begin));
    std::stable_sort(ranges.begin(), ranges.end(), [](const Range& a, const Range& b) { return a.key < b.key; });
    return ranges;
  }

  // Two halves at the object median along the widest centroid axis, ties broken by primitive index.
  std::vector<Range> medianHalves(size_t begin, size_t end) {
    Box3f centroids;
    for (size_t i = begin; i < end; ++i) centroids.extend(refs_[i].bounds.center2());
    const size_t middle = splitAtObjectMedian(refs_, begin, end, centroids);
    return {{begin, middle, 0.f}, {middle, end, 1.f}};
  }

  PrimRefs& refs_;
  size_t maxLeaf_;
  int arity_;
  BinaryBvh& out_;
  std::vector<uint8_t> cluster_;  // per position in refs_: the cluster of the node being split
  PrimRefs scratch_;
  BinaryNodeStorage* nodes_ = nullptr;  // the tree's nodes while run() makes them
};

}  // namespace

BinaryBvh buildKMeans(PrimRefs& refs, const BuildOptions& options) {
  BinaryBvh out;
  if (refs.empty()) return out;
  KMeansBuilder(refs, options, out).run();
  return out;
}

}  // namespace obvh
