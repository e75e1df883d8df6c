#include "builders/spatial_split_builder.h"

#include <tbb/parallel_invoke.h>

#include <algorithm>
#include <array>
#include <limits>
#include <memory>

#include "builders/deterministic_reduce.h"

namespace obvh {
namespace {

constexpr int kObjectBins = 32;
constexpr int kMaxSpatialBins = 64;
constexpr size_t kParallelThreshold = 4096;
constexpr int kMaxDepth = 64;  // past this, object splits at the median only (bounded stacks)

// The part of a triangle's bounding box that lies between lo and hi on one axis (the clipped
// polygon's bounds: the vertices inside the slab and the edges' crossings of its two planes).
Box3f clippedTriangleBounds(const StoredTriangle& t, int axis, float lo, float hi) {
  const Vec3f v[3] = {t.v0, t.v1, t.v2};
  Box3f box;
  for (int i = 0; i < 3; ++i) {
    const Vec3f a = v[i], b = v[(i + 1) % 3];
    if (a[axis] >= lo && a[axis] <= hi) box.extend(a);
    for (float plane : {lo, hi}) {
      const float da = a[axis] - plane, db = b[axis] - plane;
      if ((da < 0.f && db > 0.f) || (da > 0.f && db < 0.f)) {
        const float s = da / (da - db);
        Vec3f p = a + (b - a) * s;
        p[axis] = plane;  // exactly on the plane, whatever the rounding of the interpolation
        box.extend(p);
      }
    }
  }
  return box;
}

Box3f intersectBoxes(const Box3f& a, const Box3f& b) {
  Box3f r;
  r.lower = maxv(a.lower, b.lower);
  r.upper = minv(a.upper, b.upper);
  return r;
}

struct TempNode {
  Box3f bounds;
  std::unique_ptr<TempNode> left, right;
  std::vector<uint32_t> prims;  // leaves
};

struct ObjectBins {
  std::array<Box3f, kObjectBins * 3> bounds;
  std::array<uint32_t, kObjectBins * 3> counts{};
  void merge(const ObjectBins& o) {
    for (size_t i = 0; i < bounds.size(); ++i) bounds[i].extend(o.bounds[i]), counts[i] += o.counts[i];
  }
};

struct ObjectSplit {
  int axis = -1;
  int bin = 0;
  float cost = std::numeric_limits<float>::infinity();
  Box3f leftBounds, rightBounds;
  Box3f centroidBounds;
};

struct SpatialSplit {
  int axis = -1;
  float plane = 0.f;
  size_t leftCount = 0, rightCount = 0;  // references on each side (capacity hints)
  float cost = std::numeric_limits<float>::infinity();
};

class SpatialSplitBuilder {
 public:
  SpatialSplitBuilder(const StoredTriangle* triangles, const BuildOptions& options, const SpatialSplitSettings& settings,
                      float rootHalfArea)
      : triangles_(triangles), options_(options), settings_(settings), rootHalfArea_(rootHalfArea) {
    settings_.spatialBins = std::clamp(settings_.spatialBins, 2, kMaxSpatialBins);
    options_.maxLeafSize = std::max(options_.maxLeafSize, 1);
    options_.leafBlockSize = std::max(options_.leafBlockSize, 1);
  }

  std::unique_ptr<TempNode> build(std::vector<PrimRef> refs, size_t budget, int depth) const {
    auto node = std::make_unique<TempNode>();
    Box3f centroids;
    for (const PrimRef& r : refs) node->bounds.extend(r.bounds), centroids.extend(r.bounds.center2());
    const size_t n = refs.size();
    const float leafCost = options_.intersectionCost * blocks(n);
    const float area = node->bounds.halfArea();

    ObjectSplit object;
    const bool distinct = !(centroids.lower.x == centroids.upper.x && centroids.lower.y == centroids.upper.y &&
                            centroids.lower.z == centroids.upper.z);
    if (distinct && depth < kMaxDepth) object = findObjectSplit(refs, centroids);
    SpatialSplit spatial;
    if (budget > 0 && object.axis >= 0 && depth < kMaxDepth) {
      const float overlap = intersectBoxes(object.leftBounds, object.rightBounds).halfArea();
      if (overlap > settings_.overlapThreshold * rootHalfArea_) spatial = findSpatialSplit(refs, node->bounds, budget);
    }
    const float bestSplit = std::min(object.cost, spatial.cost);
    const float splitCost = options_.traversalCost + (area > 0.f ? options_.intersectionCost * bestSplit / area : leafCost);
    if (n == 1 || (n <= size_t(options_.maxLeafSize) && leafCost <= splitCost) || (!distinct && n <= size_t(options_.maxLeafSize))) {
      for (const PrimRef& r : refs) node->prims.push_back(r.index);
      return node;
    }

    std::vector<PrimRef> left, right;
    if (spatial.cost < object.cost) splitSpatially(refs, spatial, left, right);
    if (left.empty() || right.empty()) {
      left.clear(), right.clear();
      splitObjects(refs, object, centroids, left, right);
    }
    refs.clear();
    refs.shrink_to_fit();
    // Budget: what this split used is gone; the rest goes to the children by size.
    const size_t used = left.size() + right.size() - n;
    const size_t remaining = budget > used ? budget - used : 0;
    const size_t leftBudget = size_t(double(remaining) * double(left.size()) / double(left.size() + right.size()));
    const size_t rightBudget = remaining - leftBudget;
    const bool parallel = left.size() + right.size() > kParallelThreshold;
    auto buildLeft = [&] { node->left = build(std::move(left), leftBudget, depth + 1); };
    auto buildRight = [&] { node->right = build(std::move(right), rightBudget, depth + 1); };
    if (parallel) tbb::parallel_invoke(buildLeft, buildRight);
    else buildLeft(), buildRight();
    return node;
  }

 private:
  float blocks(size_t count) const {
    const size_t b = size_t(options_.leafBlockSize);
    return float((count + b - 1) / b);
  }

  ObjectSplit findObjectSplit(const std::vector<PrimRef>& refs, const Box3f& centroids) const {
    const int bins = int(std::min<size_t>(kObjectBins, std::max<size_t>(4, refs.size())));
    const Vec3f extent = centroids.upper - centroids.lower;
    Vec3f scale;
    for (int a = 0; a < 3; ++a) scale[a] = extent[a] > 0.f ? 0.99999f * float(bins) / extent[a] : 0.f;
    // Box unions and counts are exact in any order; the fixed-order reduction is for symmetry.
    const ObjectBins binned = reduceDeterministically<ObjectBins>(
        0, refs.size(),
        [&](size_t begin, size_t end, ObjectBins& acc) {
          for (size_t i = begin; i < end; ++i) {
            const Box3f& box = refs[i].bounds;
            const Vec3f c = box.center2();
            for (int a = 0; a < 3; ++a) {
              const int b = std::clamp(int((c[a] - centroids.lower[a]) * scale[a]), 0, bins - 1);
              acc.bounds[size_t(a * bins + b)].extend(box);
              ++acc.counts[size_t(a * bins + b)];
            }
          }
        },
        kParallelThreshold);
    const auto& bounds = binned.bounds;
    const auto& counts = binned.counts;
    ObjectSplit best;
    best.centroidBounds = centroids;
    std::array<Box3f, kObjectBins> rightBox;
    std::array<uint32_t, kObjectBins> rightCount;
    for (int a = 0; a < 3; ++a) {
      if (extent[a] <= 0.f) continue;
      Box3f acc;
      uint32_t count = 0;
      for (int b = bins - 1; b > 0; --b) {
        acc.extend(bounds[size_t(a * bins + b)]);
        count += counts[size_t(a * bins + b)];
        rightBox[size_t(b)] = acc, rightCount[size_t(b)] = count;
      }
      acc = Box3f{};
      count = 0;
      for (int b = 1; b < bins; ++b) {
        acc.extend(bounds[size_t(a * bins + b - 1)]);
        count += counts[size_t(a * bins + b - 1)];
        if (count == 0 || rightCount[size_t(b)] == 0) continue;
        const float cost = acc.halfArea() * blocks(count) + rightBox[size_t(b)].halfArea() * blocks(rightCount[size_t(b)]);
        if (cost < best.cost) best.axis = a, best.bin = b, best.cost = cost, best.leftBounds = acc, best.rightBounds = rightBox[size_t(b)];
      }
    }
    return best;
  }

  // Chops every reference into the spatial bins it spans (its triangle clipped to each bin's slab)
  // and sweeps for the cheapest plane whose duplicated references fit the budget; entering and
  // leaving counts give each side's references.
  SpatialSplit findSpatialSplit(const std::vector<PrimRef>& refs, const Box3f& nodeBounds, size_t budget) const {
    // The three axes' searches are independent: large nodes (the top of the tree, where the
    // subtrees are not yet parallel) run them as TBB tasks. The best plane is then chosen in axis
    // order, exactly as the sequential loop would.
    std::array<SpatialSplit, 3> perAxis;
    const auto search = [&](int a) { perAxis[size_t(a)] = findSpatialSplitOnAxis(refs, nodeBounds, budget, a); };
    if (refs.size() > kParallelThreshold) {
      tbb::parallel_invoke([&] { search(0); }, [&] { search(1); }, [&] { search(2); });
    } else {
      for (int a = 0; a < 3; ++a) search(a);
    }
    SpatialSplit best;
    for (const SpatialSplit& candidate : perAxis)
      if (candidate.cost < best.cost) best = candidate;
    return best;
  }

  SpatialSplit findSpatialSplitOnAxis(const std::vector<PrimRef>& refs, const Box3f& nodeBounds, size_t budget, int a) const {
    SpatialSplit best;
    const int bins = settings_.spatialBins;
    const float lo = nodeBounds.lower[a], extent = nodeBounds.upper[a] - lo;
    if (!(extent > 0.f)) return best;
    const float width = extent / float(bins);
    std::array<Box3f, kMaxSpatialBins> boxes;
    std::array<uint32_t, kMaxSpatialBins> entering{}, leaving{};
    const auto binOf = [&](float x) { return std::clamp(int((x - lo) / width), 0, bins - 1); };
    for (const PrimRef& r : refs) {
      const int first = binOf(r.bounds.lower[a]), last = binOf(r.bounds.upper[a]);
      ++entering[size_t(first)], ++leaving[size_t(last)];
      if (first == last) {
        boxes[size_t(first)].extend(r.bounds);
        continue;
      }
      const StoredTriangle& t = triangles_[r.index];
      for (int b = first; b <= last; ++b) {
        const float slabLo = b == first ? r.bounds.lower[a] : lo + width * float(b);
        const float slabHi = b == last ? r.bounds.upper[a] : lo + width * float(b + 1);
        boxes[size_t(b)].extend(intersectBoxes(clippedTriangleBounds(t, a, slabLo, slabHi), r.bounds));
      }
    }
    std::array<Box3f, kMaxSpatialBins> rightBox;
    std::array<uint32_t, kMaxSpatialBins> rightCount;
    Box3f acc;
    uint32_t count = 0;
    for (int b = bins - 1; b > 0; --b) {
      acc.extend(boxes[size_t(b)]);
      count += leaving[size_t(b)];
      rightBox[size_t(b)] = acc, rightCount[size_t(b)] = count;
    }
    acc = Box3f{};
    count = 0;
    for (int b = 1; b < bins; ++b) {
      acc.extend(boxes[size_t(b - 1)]);
      count += entering[size_t(b - 1)];
      if (count == 0 || rightCount[size_t(b)] == 0) continue;
      if (size_t(count) + rightCount[size_t(b)] - refs.size() > budget) continue;
      const float cost = acc.halfArea() * blocks(count) + rightBox[size_t(b)].halfArea() * blocks(rightCount[size_t(b)]);
      if (cost < best.cost)
        best.axis = a, best.plane = lo + width * float(b), best.cost = cost, best.leftCount = count,
        best.rightCount = rightCount[size_t(b)];
    }
    return best;
  }

  void splitSpatially(const std::vector<PrimRef>& refs, const SpatialSplit& split, std::vector<PrimRef>& left,
                      std::vector<PrimRef>& right) const {
    const int a = split.axis;
    left.reserve(split.leftCount), right.reserve(split.rightCount);
    for (const PrimRef& r : refs) {
      if (r.bounds.upper[a] <= split.plane) {
        left.push_back(r);
      } else if (r.bounds.lower[a] >= split.plane) {
        right.push_back(r);
      } else {
        const StoredTriangle& t = triangles_[r.index];
        const Box3f l = intersectBoxes(clippedTriangleBounds(t, a, r.bounds.lower[a], split.plane), r.bounds);
        const Box3f h = intersectBoxes(clippedTriangleBounds(t, a, split.plane, r.bounds.upper[a]), r.bounds);
        // Rounding can leave one side without a piece: keep the whole reference on the other.
        if (l.empty()) right.push_back(r);
        else if (h.empty()) left.push_back(r);
        else left.push_back({l, r.index}), right.push_back({h, r.index});
      }
    }
  }

  void splitObjects(const std::vector<PrimRef>& refs, const ObjectSplit& split, const Box3f& centroids,
                    std::vector<PrimRef>& left, std::vector<PrimRef>& right) const {
    if (split.axis >= 0) {
      const int bins = int(std::min<size_t>(kObjectBins, std::max<size_t>(4, refs.size())));
      const float extent = centroids.upper[split.axis] - centroids.lower[split.axis];
      const float scale = 0.99999f * float(bins) / extent;
      const auto goesLeft = [&](const PrimRef& r) {
        return std::clamp(int((r.bounds.center2()[split.axis] - centroids.lower[split.axis]) * scale), 0, bins - 1) < split.bin;
      };
      // Sized first: growing the vectors push by push was a tenth of the HIGH build (perf).
      const size_t leftCount = size_t(std::count_if(refs.begin(), refs.end(), goesLeft));
      left.reserve(leftCount), right.reserve(refs.size() - leftCount);
      for (const PrimRef& r : refs) (goesLeft(r) ? left : right).push_back(r);
      if (!left.empty() && !right.empty()) return;
    }
    // No usable split (identical centroids, or too deep): halve at the median of the largest axis.
    left.clear(), right.clear();
    std::vector<PrimRef> sorted = refs;
    const int axis = centroids.largestAxis();
    const size_t middle = sorted.size() / 2;
    std::nth_element(sorted.begin(), sorted.begin() + long(middle), sorted.end(), [axis](const PrimRef& x, const PrimRef& y) {
      const float cx = x.bounds.center2()[axis], cy = y.bounds.center2()[axis];
      return cx < cy || (cx == cy && x.index < y.index);
    });
    left.assign(sorted.begin(), sorted.begin() + long(middle));
    right.assign(sorted.begin() + long(middle), sorted.end());
  }

  const StoredTriangle* triangles_;
  BuildOptions options_;
  SpatialSplitSettings settings_;
  float rootHalfArea_;
};

// Depth-first into the Bvh2Node layout: children of a node are adjacent, leaves index primIndices.
void flatten(const TempNode& root, BinaryBvh& out) {
  out.nodes.assign(1, Bvh2Node{});
  struct Pending {
    const TempNode* node;
    uint32_t slot;
  };
  std::vector<Pending> stack{{&root, 0}};
  while (!stack.empty()) {
    const Pending p = stack.back();
    stack.pop_back();
    Bvh2Node& slot = out.nodes[p.slot];
    slot.bounds = p.node->bounds;
    if (!p.node->left) {
      slot.firstChildOrPrim = uint32_t(out.primIndices.size());
      slot.primCount = uint32_t(p.node->prims.size());
      out.primIndices.insert(out.primIndices.end(), p.node->prims.begin(), p.node->prims.end());
      continue;
    }
    const uint32_t left = uint32_t(out.nodes.size());
    out.nodes[p.slot].firstChildOrPrim = left;
    out.nodes[p.slot].primCount = 0;
    out.nodes.resize(out.nodes.size() + 2);
    stack.push_back({p.node->right.get(), left + 1});
    stack.push_back({p.node->left.get(), left});
  }
}

}  // namespace

BinaryBvh buildSpatialSah(const std::vector<PrimRef>& refs, const StoredTriangle* triangles, const BuildOptions& options,
                          const SpatialSplitSettings& settings) {
  BinaryBvh out;
  if (refs.empty()) return out;
  Box3f bounds;
  for (const PrimRef& r : refs) bounds.extend(r.bounds);
  const SpatialSplitBuilder builder(triangles, options, settings, bounds.halfArea());
  const size_t budget = size_t(double(settings.referenceBudget) * double(refs.size()));
  const std::unique_ptr<TempNode> root = builder.build(refs, budget, 0);
  flatten(*root, out);
  return out;
}

}  // namespace obvh
