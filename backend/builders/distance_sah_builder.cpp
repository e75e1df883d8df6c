#include "builders/distance_sah_builder.h"

#include <tbb/parallel_invoke.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include "builders/binary_node_storage.h"
#include "builders/deterministic_reduce.h"
#include "builders/object_median.h"

namespace obvh {
namespace {

constexpr int kBins = 32;
constexpr size_t kParallelRecursionThreshold = 1 << 12;
constexpr int kMedianSplitDepth = 48;

struct Bin {
  Box3f bounds;
  size_t count = 0;
  void add(const Box3f& box) {
    bounds.extend(box);
    ++count;
  }
  void merge(const Bin& o) {
    bounds.extend(o.bounds);
    count += o.count;
  }
};

struct Binning {
  std::array<Bin, 3 * kBins> bins;
  void merge(const Binning& o) {
    for (size_t i = 0; i < bins.size(); ++i) bins[i].merge(o.bins[i]);
  }
};

struct NodeInfo {
  Box3f bounds, centroids;
  void merge(const NodeInfo& o) { bounds.extend(o.bounds), centroids.extend(o.centroids); }
};

class DistanceSahBuilder {
 public:
  DistanceSahBuilder(PrimRefs& refs, const BuildOptions& options, BinaryBvh& out)
      : refs_(refs), options_(options), alpha_(std::clamp(double(options.distanceAlpha), 0.0, 1.0)), out_(out) {}

  void run() {
    buildIntoBinaryBvh(refs_, out_, [&](BinaryNodeStorage& nodes) {
      nodes_ = &nodes;
      build(0, 0, refs_.size(), 0);
      nodes_ = nullptr;
    });
  }

 private:
  struct Split {
    int axis = -1, bin = 0;  // bins [0, bin) go left
    double cost = std::numeric_limits<double>::infinity();
  };

  double blocks(size_t n) const {
    const size_t b = size_t(std::max(options_.leafBlockSize, 1));
    return double((n + b - 1) / b);
  }

  // How likely a ray from the source is to enter box, up to a common factor: 1 when the box holds
  // the source, else about the solid angle it subtends, area / (area + d^2) with d the distance
  // of its centre from the source (smooth, so that nearby candidates still compare).
  double visitWeight(const Box3f& box) const {
    const Vec3f& s = options_.distanceSource;
    if (s.x >= box.lower.x && s.y >= box.lower.y && s.z >= box.lower.z && s.x <= box.upper.x && s.y <= box.upper.y &&
        s.z <= box.upper.z)
      return 1.0;
    const double area = box.halfArea();
    const Vec3f centre = box.center2() * 0.5f - s;
    const double d2 = double(centre.x) * centre.x + double(centre.y) * centre.y + double(centre.z) * centre.z;
    return area / std::max(area + d2, 1e-30);
  }

  Split bestSplit(const Binning& binning, const NodeInfo& info, size_t n) const {
    Split best;
    const double parentArea = std::max(double(info.bounds.halfArea()), 1e-30) * blocks(n);
    const double parentWeight = std::max(visitWeight(info.bounds), 1e-30) * blocks(n);
    for (int axis = 0; axis < 3; ++axis) {
      const Bin* bins = &binning.bins[size_t(axis) * kBins];
      std::array<Bin, kBins> right;  // right[b]: bins [b, kBins)
      right[kBins - 1] = bins[kBins - 1];
      for (int b = kBins - 2; b >= 1; --b) (right[b] = right[b + 1]).merge(bins[b]);
      Bin left;
      for (int b = 1; b < kBins; ++b) {
        left.merge(bins[b - 1]);
        const Bin& r = right[b];
        if (left.count == 0 || r.count == 0) continue;
        const double sah =
            (double(left.bounds.halfArea()) * blocks(left.count) + double(r.bounds.halfArea()) * blocks(r.count)) / parentArea;
        const double fromSource =
            std::min(1.0, (visitWeight(left.bounds) * blocks(left.count) + visitWeight(r.bounds) * blocks(r.count)) / parentWeight);
        const double cost = alpha_ * sah + (1.0 - alpha_) * fromSource;
        if (cost < best.cost) best = {axis, b, cost};
      }
    }
    return best;
  }

  Box3f build(uint32_t nodeIndex, size_t begin, size_t end, int depth) {
    const size_t n = end - begin;
    const NodeInfo info = reduceDeterministically<NodeInfo>(begin, end, [&](size_t b, size_t e, NodeInfo& acc) {
      for (size_t i = b; i < e; ++i) acc.bounds.extend(refs_[i].bounds), acc.centroids.extend(refs_[i].bounds.center2());
    });
    Bvh2Node& node = nodes_->make(nodeIndex);
    node.bounds = info.bounds;
    if (n <= size_t(std::max(options_.maxLeafSize, 1))) {
      node.firstChildOrPrim = uint32_t(begin);
      node.primCount = uint32_t(n);
      return info.bounds;
    }
    const Vec3f extent = info.centroids.upper - info.centroids.lower;
    Vec3f scale;
    for (int a = 0; a < 3; ++a) scale[a] = extent[a] > 0.f ? 0.99999f * float(kBins) / extent[a] : 0.f;
    const auto binOf = [&](const PrimRef& ref, int axis) {
      return std::clamp(int((ref.bounds.center2()[axis] - info.centroids.lower[axis]) * scale[axis]), 0, kBins - 1);
    };
    size_t middle = begin;
    if (depth < kMedianSplitDepth) {
      const Binning binning = reduceDeterministically<Binning>(begin, end, [&](size_t b, size_t e, Binning& acc) {
        for (size_t i = b; i < e; ++i)
          for (int axis = 0; axis < 3; ++axis) acc.bins[size_t(axis) * kBins + binOf(refs_[i], axis)].add(refs_[i].bounds);
      });
      const Split split = bestSplit(binning, info, n);
      if (split.axis >= 0)
        middle = size_t(std::partition(refs_.begin() + long(begin), refs_.begin() + long(end),
                                       [&](const PrimRef& r) { return binOf(r, split.axis) < split.bin; }) -
                        refs_.begin());
    }
    if (middle == begin || middle == end) {  // no usable split (or too deep): object median
      middle = splitAtObjectMedian(refs_, begin, end, info.centroids);
    }
    const uint32_t left = nodes_->claimPair();
    node.firstChildOrPrim = left;
    node.primCount = 0;
    const auto buildLeft = [&] { build(left, begin, middle, depth + 1); };
    const auto buildRight = [&] { build(left + 1, middle, end, depth + 1); };
    if (n > kParallelRecursionThreshold) {
      tbb::parallel_invoke(buildLeft, buildRight);
    } else {
      buildLeft();
      buildRight();
    }
    return info.bounds;
  }

  PrimRefs& refs_;
  BuildOptions options_;
  double alpha_;
  BinaryBvh& out_;
  BinaryNodeStorage* nodes_ = nullptr;  // the tree's nodes while run() makes them
};

}  // namespace

BinaryBvh buildDistanceSah(PrimRefs& refs, const BuildOptions& options) {
  BinaryBvh out;
  if (refs.empty()) return out;
  DistanceSahBuilder(refs, options, out).run();
  return out;
}

}  // namespace obvh
