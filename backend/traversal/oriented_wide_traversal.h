// Ray queries against the wide oriented layouts (oriented_wide_bvh.h): the ray is transformed into
// the children's frames in one SIMD pass (or, on eight-wide nodes of a palette tree, once a ray
// into the palette's frames), children are visited near to far for closest hits, and
// leaves are tested as blocks of four triangles like the wide AABB layouts' leaves. Four-wide
// nodes run on SSE2, which every x86-64 CPU has; eight-wide nodes need AVX2.
#pragma once

#include "bvh/oriented_wide_bvh.h"
#include "traversal/bounds_gate.h"
#include "traversal/traversal_counters.h"
#include "traversal/triangle_leaf.h"

namespace obvh {

template <int N>
struct TriangleOrientedWideView {
  const OrientedWideBvh<N>* bvh = nullptr;
  TriangleSet set;
  float extent = 0.f;  // the largest side of the tree's box (single rays judge their coherence by it)
  GateBox gate;        // the tree's bounds, every single ray's first test
  bool empty() const { return bvh == nullptr || bvh->empty(); }
};

// The view of a tree with the bounds and extent its blocks give.
template <int N>
TriangleOrientedWideView<N> makeOrientedWideView(const OrientedWideBvh<N>& bvh, const TriangleSet& set) {
  return {&bvh, set, bvh.bounds.largestSide(), GateBox(bvh.bounds)};
}

// The node width the oriented layouts trace fastest on this CPU: 8 with AVX2, else 4.
int fastestOrientedWidth();

bool intersectClosestOrientedWide(const TriangleOrientedWideView<4>& view, Ray& ray, Hit& hit, const QueryState& state,
                                  TraversalCounters* counters = nullptr);
bool intersectAnyOrientedWide(const TriangleOrientedWideView<4>& view, const Ray& ray, const QueryState& state,
                              TraversalCounters* counters = nullptr);
// Only on CPUs with AVX2 (oriented_wide_traversal_avx2.cpp).
bool intersectClosestOrientedWide(const TriangleOrientedWideView<8>& view, Ray& ray, Hit& hit, const QueryState& state,
                                  TraversalCounters* counters = nullptr);
bool intersectAnyOrientedWide(const TriangleOrientedWideView<8>& view, const Ray& ray, const QueryState& state,
                              TraversalCounters* counters = nullptr);
// Packets of up to kMaxPacketSize rays (lane i active when bit i of active is set) through the
// eight-wide kernels: the rays that hit (oriented_wide_packets.h).
uint32_t intersectClosestOrientedWidePacket(const TriangleOrientedWideView<8>& view, Ray* rays, Hit* hits,
                                            uint32_t active, const QueryState& state);

}  // namespace obvh
