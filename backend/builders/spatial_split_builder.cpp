#include "builders/spatial_split_builder.h"

#include <tbb/parallel_invoke.h>

#include <algorithm>
#include <array>
#include <limits>
#include <memory>

#include "builders/deterministic_reduce.h"
#include "memory/huge_pages.h"

namespace obvh {
namespace {

constexpr int kObjectBins = 32;
constexpr int kMaxSpatialBins = 64;
constexpr size_t kParallelThreshold = 4096;
constexpr int kMaxDepth = 64;  // past this, object splits at the median only (bounded stacks)

// The points where the triangle's edges cross the plane at `plane` on one axis (strictly: an edge
// that only touches it adds nothing; its vertex counts as inside a slab instead).
Box3f planeCrossings(const Vec3f v[3], int axis, float plane) {
  Box3f box;
  for (int i = 0; i < 3; ++i) {
    const Vec3f a = v[i], b = v[(i + 1) % 3];
    const float da = a[axis] - plane, db = b[axis] - plane;
    if ((da < 0.f && db > 0.f) || (da > 0.f && db < 0.f)) {
      const float s = da / (da - db);
      Vec3f p = a + (b - a) * s;
      p[axis] = plane;  // exactly on the plane, whatever the rounding of the interpolation
      box.extend(p);
    }
  }
  return box;
}

Box3f verticesWithin(const Vec3f v[3], int axis, float lo, float hi) {
  Box3f box;
  for (int i = 0; i < 3; ++i)
    if (v[i][axis] >= lo && v[i][axis] <= hi) box.extend(v[i]);
  return box;
}

// The part of a triangle's bounding box that lies between lo and hi on one axis (the clipped
// polygon's bounds: the vertices inside the slab and the edges' crossings of its two planes).
Box3f clippedTriangleBounds(const StoredTriangle& t, int axis, float lo, float hi) {
  const Vec3f v[3] = {t.v0, t.v1, t.v2};
  Box3f box = verticesWithin(v, axis, lo, hi);
  box.extend(planeCrossings(v, axis, lo));
  box.extend(planeCrossings(v, axis, hi));
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
  size_t first = 0, count = 0;  // leaves: their references in the builder's array
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
  float cost = std::numeric_limits<float>::infinity();
};

class SpatialSplitBuilder {
 public:
  SpatialSplitBuilder(PrimRef* refs, const StoredTriangle* triangles, const BuildOptions& options,
                      const SpatialSplitSettings& settings, float rootHalfArea)
      : refs_(refs), triangles_(triangles), options_(options), settings_(settings), rootHalfArea_(rootHalfArea) {
    settings_.spatialBins = std::clamp(settings_.spatialBins, 2, kMaxSpatialBins);
    options_.maxLeafSize = std::max(options_.maxLeafSize, 1);
    options_.leafBlockSize = std::max(options_.leafBlockSize, 1);
  }

  // The references of a node are refs_[first, first + count), followed by `budget` free slots for
  // the duplicates its spatial splits may make: a split lays the left child's references out at
  // first and the right child's after the left's share of what is left of the budget, so every
  // subtree works in place in its own part of one array (two new vectors per node before: their
  // copies and first-touch page faults; 3-17% of the HIGH build).
  std::unique_ptr<TempNode> build(size_t first, size_t count, size_t budget, int depth) const {
    auto node = std::make_unique<TempNode>();
    PrimRef* refs = refs_ + first;
    Box3f centroids;
    for (size_t i = 0; i < count; ++i) node->bounds.extend(refs[i].bounds), centroids.extend(refs[i].bounds.center2());
    const size_t n = count;
    const float leafCost = options_.intersectionCost * blocks(n);
    const float area = node->bounds.halfArea();

    ObjectSplit object;
    const bool distinct = !(centroids.lower.x == centroids.upper.x && centroids.lower.y == centroids.upper.y &&
                            centroids.lower.z == centroids.upper.z);
    if (distinct && depth < kMaxDepth) object = findObjectSplit(refs, n, centroids);
    SpatialSplit spatial;
    if (budget > 0 && object.axis >= 0 && depth < kMaxDepth) {
      const float overlap = intersectBoxes(object.leftBounds, object.rightBounds).halfArea();
      if (overlap > settings_.overlapThreshold * rootHalfArea_) spatial = findSpatialSplit(refs, n, node->bounds, budget);
    }
    const float bestSplit = std::min(object.cost, spatial.cost);
    const float splitCost = options_.traversalCost + (area > 0.f ? options_.intersectionCost * bestSplit / area : leafCost);
    if (n == 1 || (n <= size_t(options_.maxLeafSize) && leafCost <= splitCost) || (!distinct && n <= size_t(options_.maxLeafSize))) {
      node->first = first, node->count = count;
      return node;
    }

    ChildRanges children;
    if (!(spatial.cost < object.cost && splitSpatially(refs, n, budget, spatial, children)))
      children = splitObjects(refs, n, budget, object, centroids);
    const bool parallel = children.leftCount + children.rightCount > kParallelThreshold;
    auto buildLeft = [&] { node->left = build(first, children.leftCount, children.leftBudget, depth + 1); };
    auto buildRight = [&] {
      node->right = build(first + children.rightOffset, children.rightCount, children.rightBudget, depth + 1);
    };
    if (parallel) tbb::parallel_invoke(buildLeft, buildRight);
    else buildLeft(), buildRight();
    return node;
  }

 private:
  float blocks(size_t count) const {
    const size_t b = size_t(options_.leafBlockSize);
    return float((count + b - 1) / b);
  }

  ObjectSplit findObjectSplit(const PrimRef* refs, size_t n, const Box3f& centroids) const {
    const int bins = int(std::min<size_t>(kObjectBins, std::max<size_t>(4, n)));
    const Vec3f extent = centroids.upper - centroids.lower;
    Vec3f scale;
    for (int a = 0; a < 3; ++a) scale[a] = extent[a] > 0.f ? 0.99999f * float(bins) / extent[a] : 0.f;
    // Box unions and counts are exact in any order; the fixed-order reduction is for symmetry.
    const ObjectBins binned = reduceDeterministically<ObjectBins>(
        0, n,
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
  SpatialSplit findSpatialSplit(const PrimRef* refs, size_t n, const Box3f& nodeBounds, size_t budget) const {
    // The three axes' searches are independent: large nodes (the top of the tree, where the
    // subtrees are not yet parallel) run them as TBB tasks. The best plane is then chosen in axis
    // order, exactly as the sequential loop would.
    std::array<SpatialSplit, 3> perAxis;
    const auto search = [&](int a) { perAxis[size_t(a)] = findSpatialSplitOnAxis(refs, n, nodeBounds, budget, a); };
    if (n > kParallelThreshold) {
      tbb::parallel_invoke([&] { search(0); }, [&] { search(1); }, [&] { search(2); });
    } else {
      for (int a = 0; a < 3; ++a) search(a);
    }
    SpatialSplit best;
    for (const SpatialSplit& candidate : perAxis)
      if (candidate.cost < best.cost) best = candidate;
    return best;
  }

  SpatialSplit findSpatialSplitOnAxis(const PrimRef* refs, size_t n, const Box3f& nodeBounds, size_t budget, int a) const {
    SpatialSplit best;
    const int bins = settings_.spatialBins;
    const float lo = nodeBounds.lower[a], extent = nodeBounds.upper[a] - lo;
    if (!(extent > 0.f)) return best;
    const float width = extent / float(bins);
    std::array<Box3f, kMaxSpatialBins> boxes;
    std::array<uint32_t, kMaxSpatialBins> entering{}, leaving{};
    const auto binOf = [&](float x) { return std::clamp(int((x - lo) / width), 0, bins - 1); };
    for (size_t i = 0; i < n; ++i) {
      const PrimRef& r = refs[i];
      const int first = binOf(r.bounds.lower[a]), last = binOf(r.bounds.upper[a]);
      ++entering[size_t(first)], ++leaving[size_t(last)];
      if (first == last) {
        boxes[size_t(first)].extend(r.bounds);
        continue;
      }
      // clippedTriangleBounds slab by slab, each inner plane's crossings computed once for the
      // two slabs it bounds (the clipping is most of a HIGH build).
      const StoredTriangle& t = triangles_[r.index];
      const Vec3f v[3] = {t.v0, t.v1, t.v2};
      Box3f lowerCrossings = planeCrossings(v, a, r.bounds.lower[a]);
      for (int b = first; b <= last; ++b) {
        const float slabLo = b == first ? r.bounds.lower[a] : lo + width * float(b);
        const float slabHi = b == last ? r.bounds.upper[a] : lo + width * float(b + 1);
        const Box3f upperCrossings = planeCrossings(v, a, slabHi);
        Box3f piece = verticesWithin(v, a, slabLo, slabHi);
        piece.extend(lowerCrossings);
        piece.extend(upperCrossings);
        boxes[size_t(b)].extend(intersectBoxes(piece, r.bounds));
        lowerCrossings = upperCrossings;
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
      if (size_t(count) + rightCount[size_t(b)] - n > budget) continue;
      const float cost = acc.halfArea() * blocks(count) + rightBox[size_t(b)].halfArea() * blocks(rightCount[size_t(b)]);
      if (cost < best.cost)
        best.axis = a, best.plane = lo + width * float(b), best.cost = cost;
    }
    return best;
  }

  enum class Side : uint8_t { Left, Both, Right };

  static Side sideOf(const PrimRef& r, int axis, float plane) {
    if (r.bounds.upper[axis] <= plane) return Side::Left;
    if (r.bounds.lower[axis] >= plane) return Side::Right;
    return Side::Both;
  }

  // Where a split puts the children: the left child's references at the node's first slot, the
  // right child's at rightOffset, behind the left child's share of the budget that is left (the
  // rest goes to the children by size).
  struct ChildRanges {
    size_t leftCount = 0, rightCount = 0, leftBudget = 0, rightBudget = 0, rightOffset = 0;
  };
  static ChildRanges childRanges(size_t n, size_t budget, size_t leftCount, size_t rightCount) {
    ChildRanges c;
    c.leftCount = leftCount, c.rightCount = rightCount;
    const size_t remaining = budget - (leftCount + rightCount - n);
    c.leftBudget = size_t(double(remaining) * double(leftCount) / double(leftCount + rightCount));
    c.rightBudget = remaining - c.leftBudget;
    c.rightOffset = leftCount + c.leftBudget;
    return c;
  }

  // Splits refs[0, n) at the plane, in place: triangles straddling it get a clipped piece on each
  // side (on one side only where rounding leaves the other empty). Returns false, changing
  // nothing, when the duplicates would exceed the budget (the binned estimate rounds differently
  // at bin edges) or a side would be left empty. The order of references inside a child is not kept: no choice depends on it.
  bool splitSpatially(PrimRef* refs, size_t n, size_t budget, const SpatialSplit& split, ChildRanges& out) const {
    const int a = split.axis;
    size_t count[3] = {0, 0, 0};
    for (size_t i = 0; i < n; ++i) ++count[int(sideOf(refs[i], a, split.plane))];
    const size_t straddling = count[int(Side::Both)];
    if (straddling > budget) return false;
    if (count[int(Side::Left)] == 0 || count[int(Side::Right)] == 0) {
      // Rare: a side may end up empty if rounding takes every straddling triangle's piece there.
      size_t leftPieces = 0, rightPieces = 0;
      for (size_t i = 0; i < n; ++i) {
        if (sideOf(refs[i], a, split.plane) != Side::Both) continue;
        const StoredTriangle& t = triangles_[refs[i].index];
        const Box3f& b = refs[i].bounds;
        leftPieces += !intersectBoxes(clippedTriangleBounds(t, a, b.lower[a], split.plane), b).empty();
        rightPieces += !intersectBoxes(clippedTriangleBounds(t, a, split.plane, b.upper[a]), b).empty();
      }
      if (count[int(Side::Left)] + leftPieces == 0 || count[int(Side::Right)] + rightPieces == 0) return false;
    }
    // [left | straddling | right]
    PrimRef* rightBegin = std::partition(refs, refs + n, [&](const PrimRef& r) { return sideOf(r, a, split.plane) != Side::Right; });
    PrimRef* bothBegin = std::partition(refs, rightBegin, [&](const PrimRef& r) { return sideOf(r, a, split.plane) == Side::Left; });
    PrimRefs rightPieces;
    rightPieces.reserve(straddling);
    PrimRef* leftEnd = bothBegin;
    for (PrimRef* r = bothBegin; r != rightBegin; ++r) {
      const StoredTriangle& t = triangles_[r->index];
      const Box3f l = intersectBoxes(clippedTriangleBounds(t, a, r->bounds.lower[a], split.plane), r->bounds);
      const Box3f h = intersectBoxes(clippedTriangleBounds(t, a, split.plane, r->bounds.upper[a]), r->bounds);
      if (l.empty()) {
        rightPieces.push_back(*r);
      } else if (h.empty()) {
        *leftEnd++ = *r;
      } else {
        rightPieces.push_back({h, r->index});
        *leftEnd++ = {l, r->index};
      }
    }
    const size_t wholeRight = size_t(refs + n - rightBegin);
    out = childRanges(n, budget, size_t(leftEnd - refs), rightPieces.size() + wholeRight);
    // Up to higher addresses (rightOffset >= the left count): the whole right references first,
    // behind the room for the pieces, then the pieces.
    PrimRef* destination = refs + out.rightOffset;
    std::copy_backward(rightBegin, refs + n, destination + out.rightCount);
    std::copy(rightPieces.begin(), rightPieces.end(), destination);
    return true;
  }

  // Partitions refs[0, n) by the object split in place and moves the right side to its offset.
  ChildRanges splitObjects(PrimRef* refs, size_t n, size_t budget, const ObjectSplit& split, const Box3f& centroids) const {
    size_t leftCount = 0;
    if (split.axis >= 0) {
      const int bins = int(std::min<size_t>(kObjectBins, std::max<size_t>(4, n)));
      const float extent = centroids.upper[split.axis] - centroids.lower[split.axis];
      const float scale = 0.99999f * float(bins) / extent;
      const auto goesLeft = [&](const PrimRef& r) {
        return std::clamp(int((r.bounds.center2()[split.axis] - centroids.lower[split.axis]) * scale), 0, bins - 1) < split.bin;
      };
      leftCount = size_t(std::partition(refs, refs + n, goesLeft) - refs);
    }
    if (leftCount == 0 || leftCount == n) {
      // No usable split (identical centroids, or too deep): halve at the median of the largest axis.
      const int axis = centroids.largestAxis();
      leftCount = n / 2;
      std::nth_element(refs, refs + leftCount, refs + n, [axis](const PrimRef& x, const PrimRef& y) {
        const float cx = x.bounds.center2()[axis], cy = y.bounds.center2()[axis];
        return cx < cy || (cx == cy && x.index < y.index);
      });
    }
    const ChildRanges out = childRanges(n, budget, leftCount, n - leftCount);
    std::copy_backward(refs + leftCount, refs + n, refs + out.rightOffset + out.rightCount);
    return out;
  }

  PrimRef* refs_;  // every node's references and spare slots (see build)
  const StoredTriangle* triangles_;
  BuildOptions options_;
  SpatialSplitSettings settings_;
  float rootHalfArea_;
};

// Depth-first into the Bvh2Node layout: children of a node are adjacent, leaves index primIndices.
void flatten(const TempNode& root, const PrimRef* refs, BinaryBvh& out) {
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
      slot.primCount = uint32_t(p.node->count);
      for (size_t i = 0; i < p.node->count; ++i) out.primIndices.push_back(refs[p.node->first + i].index);
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

BinaryBvh buildSpatialSah(const PrimRefs& refs, const StoredTriangle* triangles, const BuildOptions& options,
                          const SpatialSplitSettings& settings) {
  BinaryBvh out;
  if (refs.empty()) return out;
  Box3f bounds;
  for (const PrimRef& r : refs) bounds.extend(r.bounds);
  const size_t budget = size_t(double(settings.referenceBudget) * double(refs.size()));
  PrimRefs slots;
  reserveWithHugePages(slots, refs.size() + budget);
  slots.assign(refs.begin(), refs.end());
  slots.resize(refs.size() + budget);
  const SpatialSplitBuilder builder(slots.data(), triangles, options, settings, bounds.halfArea());
  const std::unique_ptr<TempNode> root = builder.build(0, refs.size(), budget, 0);
  flatten(*root, slots.data(), out);
  return out;
}

}  // namespace obvh
