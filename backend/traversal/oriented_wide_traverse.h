// Single-ray traversal of the wide oriented layouts, templated on the node vector type (four lanes
// with SSE, eight with AVX2) and the four-lane type of the triangle-block test. Included only by
// the per-ISA translation units (oriented_wide_traversal.cpp, oriented_wide_traversal_avx2.cpp),
// the AVX2 one inside its target region, as wide_traverse.h is.
#pragma once

#include <cmath>
#include <limits>

#include "bvh/oriented_wide_bvh.h"
#include "simd/double_lanes.h"
#include "traversal/box_test.h"
#include "traversal/oriented_box_test.h"
#include "traversal/oriented_wide_traversal.h"
#include "traversal/ray_coherence.h"
#include "traversal/triangle_block_leaf.h"
#include "traversal/wide_walk.h"

namespace obvh {

template <typename FN>
struct OrientedWideRay {
  FN org[3], dir[3];
  FN originNorm;
  explicit OrientedWideRay(const Ray& ray) {
    for (int a = 0; a < 3; ++a) org[a] = FN::broadcast(ray.org[a]), dir[a] = FN::broadcast(ray.dir[a]);
    originNorm = FN::broadcast(std::fabs(ray.org.x) + std::fabs(ray.org.y) + std::fabs(ray.org.z));
  }
};

// As OrientedRay::enter, lane by lane: the transformed ray against the box widened by the
// transform's rounding margin (zero for axis-aligned boxes, whose identity rows transform exactly).
// Each row's slab gives the same entry and exit as slabInterval (box_test.h), computed from the plane
// the ray meets first and the one it leaves by, picked by the sign of 1/dir (the lower plane first
// where it is clear): min and max of the two distances, and the NaN replacement, are not needed. A
// ray that does not move along the row (1/dir infinite) with its origin exactly on a plane gets a
// NaN distance there, which the accumulating max / min pass over (they return their second operand
// for a NaN), leaving that side of the slab unbounded as slabInterval's replacement does; a NaN ray
// passes over every row, as before. The lanes are one ray against a node's children
// (enterChildBoxes) or one child against a packet's rays (oriented_wide_packets.h): both run these
// operations in this order, so each lane decides as it does in the other form. lowerOf(row) and
// upperOf(row) supply the boxes' planes, frameRow(row, o, inv) the rays along one row; nearT gets
// the entry distances; returns the lanes entered within [tnear, tfar].
template <typename FN, typename LowerOf, typename UpperOf, typename FrameRow>
[[gnu::always_inline]] inline int enterBoxLanes(FN oriented, FN magnitude, FN originNorm, FN tnear, FN tfar,
                                                LowerOf&& lowerOf, UpperOf&& upperOf, FrameRow&& frameRow,
                                                FN& nearT) {
  const FN margin = oriented * FN::broadcast(2.f * kObbMarginScale) * (originNorm + magnitude);
  nearT = tnear;
  FN farT = FN::broadcast(std::numeric_limits<float>::infinity());
  for (int row = 0; row < 3; ++row) {
    FN o, inv;
    frameRow(row, o, inv);
    const FN lower = lowerOf(row) - margin, upper = upperOf(row) + margin;
    nearT = max((selectBySign(inv, lower, upper) - o) * inv, nearT);
    farT = min((selectBySign(inv, upper, lower) - o) * inv, farT);
  }
  farT = min(farT * FN::broadcast(kConservativeFarScale), tfar);
  return lessEqualMask(nearT, farT);
}

// The node's children the ray enters, with their entry distances. frameRow(row, o, inv) supplies
// the ray along one row of each child's frame.
template <typename FN, typename FrameRow>
[[gnu::always_inline]] inline int enterChildBoxes(const OrientedWideNode<FN::kWidth>& node, FN originNorm, float tnear,
                                                  float tfar, float entry[FN::kWidth], FrameRow&& frameRow) {
  FN nearT;
  const int entered = enterBoxLanes(
      FN::load(node.oriented), FN::load(node.magnitude), originNorm, FN::broadcast(tnear), FN::broadcast(tfar),
      [&](int row) { return FN::load(node.lower[row]); }, [&](int row) { return FN::load(node.upper[row]); }, frameRow,
      nearT);
  nearT.store(entry);
  return entered & node.usedMask;
}

// One frame row of a vector: a0..a2 the row (one lane a frame, or one frame for every lane).
template <typename FN>
[[gnu::always_inline]] inline FN alongRow(FN a0, FN a1, FN a2, const FN v[3]) {
  return a0 * v[0] + a1 * v[1] + a2 * v[2];
}

// The ray along one frame row. The palette's ray, the per-child transform and the packets'
// lanes all take it from here, so all round alike.
template <typename FN>
[[gnu::always_inline]] inline void rayAlongRow(FN a0, FN a1, FN a2, const FN org[3], const FN dir[3], FN& o, FN& inv) {
  o = alongRow(a0, a1, a2, org);
  inv = FN::broadcast(1.f) / alongRow(a0, a1, a2, dir);
}

// The children the ray enters within [tnear, tfar], with their entry distances: the ray is
// transformed into every child's frame.
template <typename FN>
[[gnu::always_inline]] inline int enterOrientedChildren(const OrientedWideNode<FN::kWidth>& node,
                                                        const OrientedWideRay<FN>& r, float tnear, float tfar,
                                                        float entry[FN::kWidth]) {
  return enterChildBoxes(node, r.originNorm, tnear, tfar, entry, [&](int row, FN& o, FN& inv) {
    rayAlongRow(FN::load(node.axis[row][0]), FN::load(node.axis[row][1]), FN::load(node.axis[row][2]), r.org, r.dir, o,
                inv);
  });
}

// The oriented layouts' nodes as the shared walk (wide_walk.h) sees them. No prefetch: loading
// every entered child's node (ten cache lines) early gained nothing on the stack presets.
template <typename FN>
struct OrientedWideNodes {
  const OrientedWideBvh<FN::kWidth>& bvh;
  const OrientedWideRay<FN>& ray;
  const uint32_t* children(uint32_t node) const { return bvh.nodes[node].child; }
  static constexpr bool kEntriesNonNegative = false;
  float exitLimit(float tfar) const { return tfar; }
  [[gnu::always_inline]] int enter(uint32_t node, float tnear, float tfar, float entry[FN::kWidth]) const {
    return enterOrientedChildren(bvh.nodes[node], ray, tnear, tfar, entry);
  }
  void prefetch(uint32_t) const {}
  void count(uint32_t node, TraversalCounters& counters) const {
    counters.obbTests += uint64_t(__builtin_popcount(unsigned(bvh.nodes[node].usedMask)));
  }
};

// The ray in every frame of a palette (FramePalette), one lane a frame: computed once a ray, then
// each node picks its children's lanes (lanesAt) instead of transforming the ray eight times. The
// lanes round exactly as the per-child transform does (rayAlongRow), so both paths enter the same
// children. Eight-lane vectors only: a palette has eight slots.
template <typename FN>
struct PaletteRay {
  static_assert(FN::kWidth == FramePalette::kSlots, "one lane a palette slot");
  FN org[3], inv[3];
  PaletteRay(const OrientedWideRay<FN>& r, const FramePalette& palette) {
    for (int row = 0; row < 3; ++row)
      rayAlongRow(FN::load(palette.axis[row][0]), FN::load(palette.axis[row][1]), FN::load(palette.axis[row][2]), r.org,
                  r.dir, org[row], inv[row]);
  }
};

// A palette tree's nodes: those whose children all have palette frames pick the ray's lanes, the
// others transform it per child.
template <typename FN>
struct PaletteWideNodes {
  const OrientedWideBvh<FN::kWidth>& bvh;
  const OrientedWideRay<FN>& ray;
  const PaletteRay<FN>& inPalette;
  const uint32_t* children(uint32_t node) const { return bvh.nodes[node].child; }
  static constexpr bool kEntriesNonNegative = false;
  float exitLimit(float tfar) const { return tfar; }
  [[gnu::always_inline]] int enter(uint32_t node, float tnear, float tfar, float entry[FN::kWidth]) const {
    const OrientedWideNode<FN::kWidth>& n = bvh.nodes[node];
    if (!n.inPalette) return enterOrientedChildren(n, ray, tnear, tfar, entry);
    return enterChildBoxes(n, ray.originNorm, tnear, tfar, entry, [&](int row, FN& o, FN& inv) {
      o = lanesAt(inPalette.org[row], n.paletteSlot);
      inv = lanesAt(inPalette.inv[row], n.paletteSlot);
    });
  }
  void prefetch(uint32_t) const {}
  void count(uint32_t node, TraversalCounters& counters) const {
    counters.obbTests += uint64_t(__builtin_popcount(unsigned(bvh.nodes[node].usedMask)));
  }
};

// The walk for one ray: with kPredictLanes when the application declared its rays coherent
// (QueryState::coherent) or the ray follows the thread's previous one (ray_coherence.h); the
// counted walks (metrics, heatmaps) visit the same nodes either way and keep the plain form.
template <bool kClosest, bool kCounted, int N, typename Nodes, typename LeafVisitor>
[[gnu::always_inline]] inline void walkOrientedTree(const Nodes& nodes, const TriangleOrientedWideView<N>& view,
                                                    const Ray& ray, bool declaredCoherent, LeafVisitor&& leafVisitor,
                                                    TraversalCounters* counters) {
  if constexpr (!kCounted) {
    if (declaredCoherent || worthPredicting(ray, view.extent))
      return walkWideTree<N, kClosest, false, kClosest, true>(nodes, view.bvh->rootChild, ray, leafVisitor, counters);
  }
  walkWideTree<N, kClosest, kCounted>(nodes, view.bvh->rootChild, ray, leafVisitor, counters);
}

// The leaf visitors are always inlined into the walk: GCC kept them out of line, a call with its
// prologue at every leaf visit; inlined, the stack presets' views traced 1.5-4% faster, their
// shadow rays 0-5% (drop-in, one thread, two alternations). The axis-aligned kernels keep theirs
// out of line: inlined, they measured no better (README, Performance).
// The closest-hit walk is inlined into its caller, which has just made the ray's frames (the
// palette's and the per-child form's): as a call it took them through memory and began with a
// second prologue; inlined, the stack presets' views traced 3-8% faster (drop-in, one thread, three
// alternations). The any-hit walk stays a call: inlined, its shadow rays were no faster.
// The watertight test's set-up (three divisions) is made before the walk (watertightRayFor), not at
// the first leaf as the axis-aligned kernels do (WatertightRayOnDemand): rays that pass the bounds
// gate here nearly all reach a leaf, and made early its divisions overlap the first node tests
// instead of delaying the first leaf (small-1.5k and vias-5.6k's views 1-2% faster).
template <typename FN, typename F4, bool kCounted, typename Nodes>
[[gnu::always_inline]] inline bool closestThroughNodes(const Nodes& nodes,
                                                       const TriangleOrientedWideView<FN::kWidth>& view, Ray& ray,
                                                       Hit& hit, const QueryState& state, TraversalCounters* counters) {
  const OrientedWideBvh<FN::kWidth>& bvh = *view.bvh;
  const WatertightRay watertight = watertightRayFor(ray, view.set);
  bool found = false;
  walkOrientedTree<true, kCounted>(nodes, view, ray, state.coherent, [&](uint32_t firstBlock, uint32_t blockCount) __attribute__((always_inline)) {
    const bool shortened = intersectBlocksClosest<F4, simd::DoubleLanes<FN>>(
        view.set, bvh.blocks.data(), firstBlock, blockCount, watertight, ray, hit, state);
    found |= shortened;
    return shortened;
  }, counters);
  return found;
}

template <typename FN, typename F4, bool kCounted, typename Nodes>
bool anyThroughNodes(const Nodes& nodes, const TriangleOrientedWideView<FN::kWidth>& view, const Ray& ray,
                     const QueryState& state, TraversalCounters* counters) {
  const OrientedWideBvh<FN::kWidth>& bvh = *view.bvh;
  const WatertightRay watertight = watertightRayFor(ray, view.set);
  bool found = false;
  walkOrientedTree<false, kCounted>(nodes, view, ray, state.coherent, [&](uint32_t firstBlock, uint32_t blockCount) __attribute__((always_inline)) {
    found = intersectBlocksAny<F4, simd::DoubleLanes<FN>>(view.set, bvh.blocks.data(), firstBlock, blockCount,
                                                          watertight, ray, state);
    return found;
  }, counters);
  return found;
}

// The tree's bounds (bounds_gate.h), counted as one axis-aligned volume test.
template <typename F4, bool kCounted, int N>
[[gnu::always_inline]] inline bool passesGate(const TriangleOrientedWideView<N>& view, const Ray& ray,
                                              TraversalCounters* counters) {
  if constexpr (kCounted) ++counters->aabbTests;
  return mayEnterBox<F4>(view.gate, ray);
}

// Each child's frame transformed per node; kUsePalette: a palette tree's frames transformed once
// a ray (eight-lane vectors only).
template <typename FN, typename F4, bool kCounted, bool kUsePalette = false>
bool closestInOrientedWide(const TriangleOrientedWideView<FN::kWidth>& view, Ray& ray, Hit& hit,
                           const QueryState& state, TraversalCounters* counters) {
  const OrientedWideBvh<FN::kWidth>& bvh = *view.bvh;
  if (bvh.empty() || !passesGate<F4, kCounted>(view, ray, counters)) return false;
  const OrientedWideRay<FN> r(ray);
  if constexpr (kUsePalette) {
    const PaletteRay<FN> p(r, bvh.palette);
    return closestThroughNodes<FN, F4, kCounted>(PaletteWideNodes<FN>{bvh, r, p}, view, ray, hit, state, counters);
  } else {
    return closestThroughNodes<FN, F4, kCounted>(OrientedWideNodes<FN>{bvh, r}, view, ray, hit, state, counters);
  }
}

template <typename FN, typename F4, bool kCounted, bool kUsePalette = false>
bool anyInOrientedWide(const TriangleOrientedWideView<FN::kWidth>& view, const Ray& ray, const QueryState& state,
                       TraversalCounters* counters) {
  const OrientedWideBvh<FN::kWidth>& bvh = *view.bvh;
  if (bvh.empty() || !passesGate<F4, kCounted>(view, ray, counters)) return false;
  const OrientedWideRay<FN> r(ray);
  if constexpr (kUsePalette) {
    const PaletteRay<FN> p(r, bvh.palette);
    return anyThroughNodes<FN, F4, kCounted>(PaletteWideNodes<FN>{bvh, r, p}, view, ray, state, counters);
  } else {
    return anyThroughNodes<FN, F4, kCounted>(OrientedWideNodes<FN>{bvh, r}, view, ray, state, counters);
  }
}

// The uncounted instantiation for the normal query path, the counted one for the layout metrics.
template <typename FN, typename F4, bool kUsePalette = false>
bool intersectClosestOrientedWideImpl(const TriangleOrientedWideView<FN::kWidth>& view, Ray& ray, Hit& hit,
                                      const QueryState& state, TraversalCounters* counters) {
  return counters ? closestInOrientedWide<FN, F4, true, kUsePalette>(view, ray, hit, state, counters)
                  : closestInOrientedWide<FN, F4, false, kUsePalette>(view, ray, hit, state, nullptr);
}

template <typename FN, typename F4, bool kUsePalette = false>
bool intersectAnyOrientedWideImpl(const TriangleOrientedWideView<FN::kWidth>& view, const Ray& ray,
                                  const QueryState& state, TraversalCounters* counters) {
  return counters ? anyInOrientedWide<FN, F4, true, kUsePalette>(view, ray, state, counters)
                  : anyInOrientedWide<FN, F4, false, kUsePalette>(view, ray, state, nullptr);
}

}  // namespace obvh
