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
#include "traversal/stack_entry.h"
#include "traversal/triangle_block_leaf.h"

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

// The children the ray enters within [tnear, tfar], with their entry distances. Per child as in
// OrientedRay::enter: the transformed ray against the box widened by the transform's rounding
// margin (zero for axis-aligned children, whose identity rows transform exactly). A ray that does
// not move along a frame axis (1/dir infinite) gets -inf..+inf from a slab that holds its origin
// and an empty interval from one that does not; an origin exactly on a plane makes that plane's
// distance 0 * inf = NaN, replaced by the value that leaves the slab unbounded on that side
// (-1/dir for the lower plane, 1/dir for the upper), so the ray counts as inside, as in the
// scalar box test.
template <typename FN>
[[gnu::always_inline]] inline int enterOrientedChildren(const OrientedWideNode<FN::kWidth>& node,
                                                        const OrientedWideRay<FN>& r, float tnear, float tfar,
                                                        float entry[FN::kWidth]) {
  const FN margin =
      FN::load(node.oriented) * FN::broadcast(2.f * kObbMarginScale) * (r.originNorm + FN::load(node.magnitude));
  FN nearT = FN::broadcast(tnear), farT = FN::broadcast(std::numeric_limits<float>::infinity());
  for (int row = 0; row < 3; ++row) {
    const FN a0 = FN::load(node.axis[row][0]), a1 = FN::load(node.axis[row][1]), a2 = FN::load(node.axis[row][2]);
    const FN o = a0 * r.org[0] + a1 * r.org[1] + a2 * r.org[2];
    const FN d = a0 * r.dir[0] + a1 * r.dir[1] + a2 * r.dir[2];
    const FN inv = FN::broadcast(1.f) / d;
    const FN t0 = replaceNaN((FN::load(node.lower[row]) - margin - o) * inv, FN::broadcast(0.f) - inv);
    const FN t1 = replaceNaN((FN::load(node.upper[row]) + margin - o) * inv, inv);
    nearT = max(min(t0, t1), nearT);
    farT = min(max(t0, t1), farT);
  }
  farT = min(farT * FN::broadcast(kConservativeFarScale), FN::broadcast(tfar));
  nearT.store(entry);
  return lessEqualMask(nearT, farT) & node.usedMask;
}

// leafVisitor(firstBlock, blockCount) returns true to stop. Closest-hit queries visit children near
// to far and skip pending ones entered beyond the (shrinking) tfar.
template <typename FN, bool kNearToFar, typename LeafVisitor>
void traverseOrientedWide(const OrientedWideBvh<FN::kWidth>& bvh, const Ray& ray, TraversalCounters* counters,
                          LeafVisitor&& leafVisitor) {
  constexpr int N = FN::kWidth;
  using Codes = WideNode<N>;
  if (bvh.empty()) return;
  const OrientedWideRay<FN> r(ray);
  StackEntry stack[(N - 1) * 128];
  int top = 0;
  alignas(32) float entry[N];
  uint32_t current = bvh.rootChild;
  for (;;) {
    bool descended = false;
    if (Codes::isLeaf(current)) {
      if (counters) ++counters->leafVisits;
      if (leafVisitor(Codes::leafFirstBlock(current), Codes::leafBlockCount(current))) return;
    } else {
      const OrientedWideNode<N>& node = bvh.nodes[current];
      if (counters)
        for (int m = node.usedMask; m; m &= m - 1) ++counters->obbTests;
      int mask = enterOrientedChildren(node, r, ray.tnear, ray.tfar, entry);
      if (mask) {
        StackEntry entered[N];
        int n = 0;
        for (; mask; mask &= mask - 1) {
          const int lane = __builtin_ctz(unsigned(mask));
          const StackEntry e{node.child[lane], entry[lane]};
          int k = n++;
          while (kNearToFar && k > 0 && entered[k - 1].t() > e.t()) {
            entered[k] = entered[k - 1];
            --k;
          }
          entered[k] = e;
        }
        for (int k = n - 1; k >= 1; --k) stack[top++] = entered[k];
        current = entered[0].child();
        descended = true;
      }
    }
    if (descended) continue;
    for (;;) {
      if (top == 0) return;
      const StackEntry e = stack[--top];
      if (e.t() > ray.tfar) continue;
      current = e.child();
      break;
    }
  }
}

template <typename FN, typename F4>
bool intersectClosestOrientedWideImpl(const TriangleOrientedWideView<FN::kWidth>& view, Ray& ray, Hit& hit,
                                      const QueryState& state, TraversalCounters* counters) {
  const WatertightRay wr(ray);
  const TriangleBlock4* blocks = view.bvh->blocks.data();
  bool found = false;
  traverseOrientedWide<FN, true>(*view.bvh, ray, counters, [&](uint32_t firstBlock, uint32_t blockCount) {
    found |= intersectBlocksClosest<F4, simd::DoubleLanes<FN>>(view.set, blocks, firstBlock, blockCount, wr, ray, hit, state);
    return false;
  });
  return found;
}

template <typename FN, typename F4>
bool intersectAnyOrientedWideImpl(const TriangleOrientedWideView<FN::kWidth>& view, const Ray& ray,
                                  const QueryState& state, TraversalCounters* counters) {
  const WatertightRay wr(ray);
  const TriangleBlock4* blocks = view.bvh->blocks.data();
  bool found = false;
  traverseOrientedWide<FN, false>(*view.bvh, ray, counters, [&](uint32_t firstBlock, uint32_t blockCount) {
    found = intersectBlocksAny<F4, simd::DoubleLanes<FN>>(view.set, blocks, firstBlock, blockCount, wr, ray, state);
    return found;
  });
  return found;
}

}  // namespace obvh
