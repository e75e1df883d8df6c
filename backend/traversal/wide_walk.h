// The single-ray walk shared by the wide layouts (axis-aligned: wide_traverse.h; oriented:
// oriented_wide_traverse.h). Both code their children as WideNode<N> does (node index, leaf of
// blocks, empty); they differ only in how a node's child volumes are entered, which the layout's
// Nodes type supplies:
//   const uint32_t* children(uint32_t node)          the node's child codes
//   Limit exitLimit(float tfar)                       tfar in the form enter takes it, prepared once
//                                                     each time tfar changes rather than at every node
//   int enter(uint32_t node, float tnear, const Limit& tfar, float entry[N])
//                                                     mask of the entered children, entry distances
//   void prefetch(uint32_t child)                     start loading a child before it is visited
//   void count(uint32_t node, TraversalCounters&)     add the node's volume tests
//   static constexpr bool kEntriesNonNegative          every entry distance enter reports for an
//                                                     entered child is +0 or positive
// Included only by the per-ISA translation units, inside their target region, as its callers are.
#pragma once

#include <cstddef>
#include <cstdint>

#include "bvh/wide_bvh.h"
#include "intersect/ray.h"
#include "math/float_steps.h"
#include "traversal/child_order.h"
#include "traversal/stack_entry.h"
#include "traversal/traversal_counters.h"

namespace obvh {

// The child in lane `lane`, read as one of N loads at fixed offsets behind branches on the lane
// instead of as an indexed load: the next node's address then no longer waits for this node's
// test (its mask, the lane, the load); the branch predictor guesses the lane, the next node's loads
// start at once, and the test only confirms the guess. Where consecutive rays take the same paths
// (camera rays, shadow rays to one light) it guesses well, and the oriented layouts, whose node
// test is a long chain (a transform per child), traced the stack presets' views 10-20% faster.
// Wrong guesses cost more than the wait they save: the axis-aligned kernels, whose node test is
// short, lost 5-8% on incoherent rays and on the motorBike's primary rays when they guessed for
// every ray or after checking the previous ray, so they guess only for rays the application declares
// coherent (QueryState::coherent): camera rays 3-10% faster, shadow rays to one light 5-15%.
template <int N>
[[gnu::always_inline]] inline uint32_t childOfPredictedLane(const uint32_t* child, size_t lane) {
  static_assert(N == 4 || N == 8);
  // Two switches of four, not one of eight: GCC compiles the one of eight into a jump table,
  // whose single indirect branch was guessed no better than this tree of compares (README,
  // Oriented layouts, 2026-11-26).
  switch (lane) {
    case 0: return child[0];
    case 1: return child[1];
    case 2: return child[2];
    case 3: return child[3];
    default: break;
  }
  if constexpr (N == 8) {
    switch (lane) {
      case 4: return child[4];
      case 5: return child[5];
      case 6: return child[6];
      default: return child[7];
    }
  }
  return child[3];
}

// The lowest lane of a non-empty mask, counted straight into a 64-bit register: GCC sign-extends
// __builtin_ctz's int (a movslq, whatever the casts) before it indexes the node's child codes, one
// more step on the chain from a node's test to the next node's loads. tzcnt runs as bsf on CPUs
// without BMI1, which counts a non-empty mask the same.
[[gnu::always_inline]] inline size_t lowestLane(int mask) {
  size_t lane;
  asm("tzcnt %1, %0" : "=r"(lane) : "r"(uint64_t(unsigned(mask))) : "cc");
  return lane;
}

// The child a node's walk goes to next, of the entered children `mask` (not empty) with their
// entry distances; the others are pushed, farthest first. See walkWideTree for the template
// parameters.
template <int N, bool kClosest, bool kSorted, bool kPredictLanes, typename Nodes, typename Stack>
[[gnu::always_inline]] inline uint32_t nextChildPushingOthers(const Nodes& nodes, const uint32_t* child, int mask,
                                                              const float entry[N], Stack* stack, int& top) {
  if ((mask & (mask - 1)) == 0) {  // one child entered: no sorting, no stack
    const size_t lane = lowestLane(mask);
    return kPredictLanes ? childOfPredictedLane<N>(child, lane) : child[lane];
  }
  if (!kSorted && !kClosest) {
    const size_t first = lowestLane(mask);
    const uint32_t next = kPredictLanes ? childOfPredictedLane<N>(child, first) : child[first];
    mask &= mask - 1;
    while (mask) {
      const size_t lane = lowestLane(mask);
      mask &= mask - 1;
      nodes.prefetch(child[lane]);
      stack[top++] = {child[lane], entry[lane]};
    }
    return next;
  }
  if (!kSorted) {  // lane order: the lowest lane now, the others pushed highest first
    const uint32_t next = child[lowestLane(mask)];
    mask &= mask - 1;
    while (mask) {
      const int lane = 31 - __builtin_clz(unsigned(mask));
      mask &= ~(1 << lane);
      nodes.prefetch(child[lane]);
      stack[top++] = {child[lane], entry[lane]};
    }
    return next;
  }
  // Two children, the most common case after one: the nearer is visited first (the lower lane
  // on equal distances, as in the general sort below).
  const size_t first = lowestLane(mask);
  const int rest = mask & (mask - 1);
  if ((rest & (rest - 1)) == 0) {
    const size_t second = lowestLane(rest);
    const bool firstNearer = entry[first] <= entry[second];
    const size_t nearLane = firstNearer ? first : second, farLane = firstNearer ? second : first;
    // The predicted walk prefetches neither: it loads the child it guesses at once (that prefetch
    // would only cost the instructions: bunny camera rays 2% faster without it, motorBike and
    // dragon the same), and the coherent rays it serves mostly drop the farther child at its pop,
    // behind the hit they found (without that prefetch either: motorBike camera rays 2.2% faster,
    // orthographic 1.5%, bunny 1.2%, dragon the same).
    if constexpr (!kPredictLanes) {
      nodes.prefetch(child[nearLane]);
      nodes.prefetch(child[farLane]);
    }
    stack[top++] = {child[farLane], entry[farLane]};
    return kPredictLanes ? childOfPredictedLane<N>(child, nearLane) : child[nearLane];
  }
  // Three or more: sorted near to far (lower lane first on equal distances) without branches
  // (child_order.h); the farther ones pushed farthest first.
  int64_t keys[8];
  int n = 0;
  while (mask) {
    const int lane = __builtin_ctz(unsigned(mask));
    mask &= mask - 1;
    if constexpr (!kPredictLanes) nodes.prefetch(child[lane]);
    keys[n++] = Nodes::kEntriesNonNegative ? childOrderKeyOfNonNegative(entry[lane], lane) : childOrderKey(entry[lane], lane);
  }
  sortChildOrderKeys(keys, n);
  for (int k = n - 1; k >= 1; --k) {
    const int lane = childOrderLane(keys[k]);
    // The predicted walk prefetches none of them (see the case of two).
    stack[top++] = {child[lane], entry[lane]};
  }
  const int nearest = childOrderLane(keys[0]);
  return kPredictLanes ? childOfPredictedLane<N>(child, nearest) : child[nearest];
}

// What a walk does once the ray is known to enter the tree: nothing by default.
struct NothingOnEntering {
  void operator()() const {}
};

// Visits the leaves the ray enters. kClosest: a closest-hit query, whose leaves shorten the ray;
// leafVisitor(firstBlock, blockCount) returns true when the leaf did (accepted a hit), and only then
// does the walk take the new tfar into its limits, which a leaf without a hit (most of them: a
// diffuse bounce on the bunny visits about two leaves and hits in under a tenth of them) leaves
// unchanged. For an any-hit query, true stops the walk.
// kSorted: the entered children of a node are visited near to far (closest hit's default); else in
// the node's lane order (larger first, see the collapse), which any-hit queries use and closest-hit
// ones may (device config child_order=fixed). kCounted adds volume tests and leaf visits to
// *counters (a separate instantiation, so the normal path pays nothing). kPredictLanes: the child
// visited next is read behind a branch on its lane (childOfPredictedLane), for rays that follow
// the previous ray closely (ray_coherence.h) or that the application declared coherent; else by
// its lane as an index.
// onEntering() runs once, before the first leaf, as soon as the start node's test lets the ray in
// (or before visiting a start node that is a leaf): the leaves' per-ray set-up made there overlaps
// the next node tests, where made at the first leaf it waited on them, and it is still skipped by
// rays that the start node's boxes turn away. The start node's test is peeled off the loop for it,
// so no flag is tested per leaf (the flag of a set-up made at the first leaf, which leaf visit is a
// ray's first being unpredictable, cost 0.63 mispredicted branches a diffuse bounce on the bunny).
// Always inlined, so that the ray's per-layout data stays in registers (passed by reference to a
// call it cost ~15 instructions a ray).
template <int N, bool kClosest, bool kCounted, bool kSorted = kClosest, bool kPredictLanes = false, typename Nodes,
          typename LeafVisitor, typename OnEntering = NothingOnEntering>
[[gnu::always_inline]] inline void walkWideTree(const Nodes& nodes, uint32_t start, const Ray& ray,
                                                LeafVisitor&& leafVisitor, TraversalCounters* counters,
                                                OnEntering&& onEntering = {}) {
  using Codes = WideNode<N>;
  // Once a closest-hit query has a hit (tfar shrank), a volume entered exactly at tfar can only add
  // hits at that same distance: an equally valid answer, not a closer one. Skipping such volumes
  // matters for rays parallel to flat layers, where many boxes share the entry distance.
  // Both cases in one bound: volumes entered beyond limit are skipped, and once there is a hit
  // limit is the float just below tfar (x <= nextafter(t, -inf) exactly when x < t).
  const float initialTfar = ray.tfar;
  float limit = ray.tfar;
  auto exitLimit = nodes.exitLimit(limit);
  const auto updateLimit = [&] {
    limit = kClosest && ray.tfar < initialTfar ? nextFloatDown(ray.tfar) : ray.tfar;
    exitLimit = nodes.exitLimit(limit);
  };
  StackEntry stack[(N - 1) * 128];
  int top = 0;
  alignas(32) float entry[N];
  // The root starts in a register: pushed and popped at once, it cost a store-forwarding stall
  // (a third of the time of a ray missing the scene before StackEntry existed).
  if (ray.tnear > limit) return;
  uint32_t current = start;
  if (!Codes::isLeaf(current)) {
    if constexpr (kCounted) nodes.count(current, *counters);
    const uint32_t* child = nodes.children(current);
    const int mask = nodes.enter(current, ray.tnear, exitLimit, entry);
    if (mask == 0) return;
    onEntering();
    current = nextChildPushingOthers<N, kClosest, kSorted, kPredictLanes>(nodes, child, mask, entry, stack, top);
  } else {
    onEntering();
  }
  for (;;) {
    for (;;) {
      if (Codes::isLeaf(current)) {
        if constexpr (kCounted) ++counters->leafVisits;
        if (leafVisitor(Codes::leafFirstBlock(current), Codes::leafBlockCount(current))) {
          if constexpr (!kClosest) return;
          updateLimit();
        }
        break;
      }
      if constexpr (kCounted) nodes.count(current, *counters);
      const uint32_t* child = nodes.children(current);
      const int mask = nodes.enter(current, ray.tnear, exitLimit, entry);
      if (mask == 0) break;
      current = nextChildPushingOthers<N, kClosest, kSorted, kPredictLanes>(nodes, child, mask, entry, stack, top);
    }
    for (;;) {
      if (top == 0) return;
      const StackEntry e = stack[--top];
      if (e.t() > limit) continue;
      current = e.child();
      break;
    }
  }
}

}  // namespace obvh
