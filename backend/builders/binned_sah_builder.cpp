#include "builders/binned_sah_builder.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_invoke.h>
#include <tbb/parallel_reduce.h>

#include <algorithm>
#include <array>
#include <atomic>

namespace obvh {
namespace {

constexpr int kMaxBins = 256;
// Below these sizes the overhead of spawning tasks outweighs the parallel speed-up.
constexpr size_t kParallelBinningThreshold = 1 << 16;
constexpr size_t kParallelRecursionThreshold = 1 << 12;
// Past this depth the builder splits at the object median, which bounds the depth by
// kMedianSplitDepth + log2(N) and so keeps traversal stacks small and fixed.
constexpr int kMedianSplitDepth = 48;

struct RangeInfo {
  Box3f bounds;
  Box3f centroidBounds;  // bounds of twice the centroids (see Box3f::center2)

  void add(const PrimRef& ref) {
    bounds.extend(ref.bounds);
    centroidBounds.extend(ref.bounds.center2());
  }
  void merge(const RangeInfo& other) {
    bounds.extend(other.bounds);
    centroidBounds.extend(other.centroidBounds);
  }
};

// Sized to the configured bin count: clearing all kMaxBins entries per node would dominate build time.
struct Bins {
  int binCount = 0;
  std::vector<Box3f> boundsStorage;
  std::vector<uint32_t> countStorage;

  explicit Bins(int bins = 0) : binCount(bins), boundsStorage(3 * size_t(bins)), countStorage(3 * size_t(bins), 0) {}
  Box3f& bounds(int axis, int b) { return boundsStorage[size_t(axis) * binCount + b]; }
  const Box3f& bounds(int axis, int b) const { return boundsStorage[size_t(axis) * binCount + b]; }
  uint32_t& count(int axis, int b) { return countStorage[size_t(axis) * binCount + b]; }
  uint32_t count(int axis, int b) const { return countStorage[size_t(axis) * binCount + b]; }

  void merge(const Bins& other) {
    if (binCount == 0) {
      *this = other;
      return;
    }
    for (size_t i = 0; i < boundsStorage.size() && i < other.boundsStorage.size(); ++i) {
      boundsStorage[i].extend(other.boundsStorage[i]);
      countStorage[i] += other.countStorage[i];
    }
  }
};

// Maps a centroid coordinate to a bin index; identical arithmetic is used for binning and partitioning.
struct BinMapping {
  Vec3f origin;
  Vec3f scale;
  int binCount;

  BinMapping(const Box3f& centroidBounds, int bins) : origin(centroidBounds.lower), binCount(bins) {
    const Vec3f extent = centroidBounds.upper - centroidBounds.lower;
    for (int axis = 0; axis < 3; ++axis)
      scale[axis] = extent[axis] > 0.f ? (0.99999f * float(bins)) / extent[axis] : 0.f;
  }
  int bin(const PrimRef& ref, int axis) const {
    const int b = int((ref.bounds.center2()[axis] - origin[axis]) * scale[axis]);
    return std::clamp(b, 0, binCount - 1);
  }
};

struct Split {
  int axis = -1;
  int bin = 0;  // primitives in bins [0, bin) go left
  float cost = std::numeric_limits<float>::infinity();
};

class BinnedSahBuilder {
 public:
  BinnedSahBuilder(std::vector<PrimRef>& refs, const BuildOptions& options, BinaryBvh& out)
      : refs_(refs), options_(options), out_(out) {
    options_.binCount = std::clamp(options_.binCount, 2, kMaxBins);
    options_.maxLeafSize = std::max(options_.maxLeafSize, 1);
    options_.leafBlockSize = std::max(options_.leafBlockSize, 1);
  }

  void run() {
    const size_t n = refs_.size();
    out_.nodes.clear();
    out_.primIndices.clear();
    if (n == 0) return;
    out_.nodes.resize(2 * n - 1);
    nodeCount_ = 1;
    buildNode(0, 0, n, rangeInfo(0, n), 0);
    out_.nodes.resize(nodeCount_.load());
    out_.primIndices.resize(n);
    for (size_t i = 0; i < n; ++i) out_.primIndices[i] = refs_[i].index;
  }

 private:
  RangeInfo rangeInfo(size_t begin, size_t end) const {
    if (end - begin < kParallelBinningThreshold) {
      RangeInfo info;
      for (size_t i = begin; i < end; ++i) info.add(refs_[i]);
      return info;
    }
    return tbb::parallel_reduce(
        tbb::blocked_range<size_t>(begin, end, 4096), RangeInfo{},
        [&](const tbb::blocked_range<size_t>& r, RangeInfo info) {
          for (size_t i = r.begin(); i < r.end(); ++i) info.add(refs_[i]);
          return info;
        },
        [](RangeInfo a, const RangeInfo& b) {
          a.merge(b);
          return a;
        });
  }

  void binRange(size_t begin, size_t end, const BinMapping& mapping, Bins& bins) const {
    for (size_t i = begin; i < end; ++i)
      for (int axis = 0; axis < 3; ++axis) {
        const int b = mapping.bin(refs_[i], axis);
        bins.bounds(axis, b).extend(refs_[i].bounds);
        ++bins.count(axis, b);
      }
  }

  Bins binAll(size_t begin, size_t end, const BinMapping& mapping) const {
    const int binCount = mapping.binCount;
    if (end - begin < kParallelBinningThreshold) {
      Bins bins(binCount);
      binRange(begin, end, mapping, bins);
      return bins;
    }
    return tbb::parallel_reduce(
        tbb::blocked_range<size_t>(begin, end, 8192), Bins(binCount),
        [&](const tbb::blocked_range<size_t>& r, Bins bins) {
          binRange(r.begin(), r.end(), mapping, bins);
          return bins;
        },
        [](Bins a, const Bins& b) {
          a.merge(b);
          return a;
        });
  }

  // Leaves are tested leafBlockSize primitives at a time: a partly filled block costs a full one.
  float blocks(size_t count) const {
    const size_t b = size_t(options_.leafBlockSize);
    return float((count + b - 1) / b);
  }

  Split findBestSplit(const Bins& bins, int binCount) const {
    Split best;
    std::array<float, kMaxBins> rightCost{};
    std::array<uint32_t, kMaxBins> rightCount{};
    for (int axis = 0; axis < 3; ++axis) {
      Box3f accumulated;
      uint32_t count = 0;
      for (int b = binCount - 1; b > 0; --b) {
        accumulated.extend(bins.bounds(axis, b));
        count += bins.count(axis, b);
        rightCost[b] = accumulated.halfArea() * blocks(count);
        rightCount[b] = count;
      }
      accumulated = Box3f{};
      count = 0;
      for (int b = 1; b < binCount; ++b) {
        accumulated.extend(bins.bounds(axis, b - 1));
        count += bins.count(axis, b - 1);
        const float cost = accumulated.halfArea() * blocks(count) + rightCost[b];
        if (count > 0 && rightCount[b] > 0 && cost < best.cost) best = Split{axis, b, cost};
      }
    }
    return best;
  }

  // Partitions [begin, end) by goesLeft and measures both sides on the way, which saves the
  // children a separate pass over their primitives. Returns the first index of the right side.
  template <typename GoesLeft>
  size_t partitionMeasuring(size_t begin, size_t end, GoesLeft&& goesLeft, RangeInfo& left, RangeInfo& right) {
    size_t i = begin, j = end;
    for (;;) {
      while (i < j && goesLeft(refs_[i])) left.add(refs_[i++]);
      while (i < j && !goesLeft(refs_[j - 1])) right.add(refs_[--j]);
      if (i >= j) return i;
      std::swap(refs_[i], refs_[j - 1]);
      left.add(refs_[i++]);
      right.add(refs_[--j]);
    }
  }

  void makeLeaf(uint32_t nodeIndex, size_t begin, size_t end, const Box3f& bounds) {
    Bvh2Node& node = out_.nodes[nodeIndex];
    node.bounds = bounds;
    node.firstChildOrPrim = uint32_t(begin);
    node.primCount = uint32_t(end - begin);
  }

  void buildNode(uint32_t nodeIndex, size_t begin, size_t end, const RangeInfo& info, int depth) {
    const size_t n = end - begin;
    if (n == 1) return makeLeaf(nodeIndex, begin, end, info.bounds);

    size_t middle = begin;
    RangeInfo leftInfo, rightInfo;
    bool childInfoKnown = false;  // set when the partition already measured both sides
    // Small nodes cannot use many bins; sweeping empty bins would dominate the build time.
    const int binCount = int(std::min<size_t>(size_t(options_.binCount), std::max<size_t>(4, 2 * n)));
    const BinMapping mapping(info.centroidBounds, binCount);
    const bool centroidsDistinct = !(info.centroidBounds.lower.x == info.centroidBounds.upper.x &&
                                     info.centroidBounds.lower.y == info.centroidBounds.upper.y &&
                                     info.centroidBounds.lower.z == info.centroidBounds.upper.z);
    if (centroidsDistinct && depth >= kMedianSplitDepth) {
      if (n <= size_t(options_.maxLeafSize)) return makeLeaf(nodeIndex, begin, end, info.bounds);
      const int axis = info.centroidBounds.largestAxis();
      middle = begin + n / 2;
      std::nth_element(refs_.begin() + begin, refs_.begin() + middle, refs_.begin() + end,
                       [axis](const PrimRef& a, const PrimRef& b) {
                         return a.bounds.center2()[axis] < b.bounds.center2()[axis];
                       });
    } else if (centroidsDistinct) {
      const Bins bins = binAll(begin, end, mapping);
      const Split split = findBestSplit(bins, binCount);
      const float parentArea = info.bounds.halfArea();
      const float leafCost = options_.intersectionCost * blocks(n);
      const float splitCost =
          options_.traversalCost +
          (parentArea > 0.f ? options_.intersectionCost * split.cost / parentArea : leafCost);
      if (n <= size_t(options_.maxLeafSize) && leafCost <= splitCost)
        return makeLeaf(nodeIndex, begin, end, info.bounds);
      if (split.axis >= 0) {
        auto goesLeft = [&](const PrimRef& ref) { return mapping.bin(ref, split.axis) < split.bin; };
        if (n < kParallelBinningThreshold) {
          middle = partitionMeasuring(begin, end, goesLeft, leftInfo, rightInfo);
          childInfoKnown = true;
        } else {  // large ranges: measure the children with the parallel reduction instead
          middle = size_t(std::partition(refs_.begin() + begin, refs_.begin() + end, goesLeft) - refs_.begin());
        }
      }
    } else if (n <= size_t(options_.maxLeafSize)) {
      return makeLeaf(nodeIndex, begin, end, info.bounds);
    }
    // Identical centroids or a failed partition: halve the range so recursion always terminates.
    if (middle == begin || middle == end) {
      middle = begin + n / 2;
      childInfoKnown = false;
    }

    const uint32_t left = nodeCount_.fetch_add(2);
    Bvh2Node& node = out_.nodes[nodeIndex];
    node.bounds = info.bounds;
    node.firstChildOrPrim = left;
    node.primCount = 0;

    auto buildLeft = [&] {
      buildNode(left, begin, middle, childInfoKnown ? leftInfo : rangeInfo(begin, middle), depth + 1);
    };
    auto buildRight = [&] {
      buildNode(left + 1, middle, end, childInfoKnown ? rightInfo : rangeInfo(middle, end), depth + 1);
    };
    if (n > kParallelRecursionThreshold) {
      tbb::parallel_invoke(buildLeft, buildRight);
    } else {
      buildLeft();
      buildRight();
    }
  }

  std::vector<PrimRef>& refs_;
  BuildOptions options_;
  BinaryBvh& out_;
  std::atomic<uint32_t> nodeCount_{0};
};

}  // namespace

BinaryBvh buildBinnedSah(std::vector<PrimRef>& refs, const BuildOptions& options) {
  BinaryBvh bvh;
  BinnedSahBuilder(refs, options, bvh).run();
  return bvh;
}

}  // namespace obvh
