// Ray queries against the four-wide oriented layout (oriented_wide_bvh.h): the ray is transformed
// into the four children's frames in one SSE pass, children are visited near to far for closest
// hits, and leaves are tested as blocks of four triangles like the wide AABB layouts' leaves.
// SSE2 only, which every x86-64 CPU has, so there is one kernel and no run-time choice.
#pragma once

#include "bvh/oriented_wide_bvh.h"
#include "traversal/traversal_counters.h"
#include "traversal/triangle_leaf.h"

namespace obvh {

struct TriangleOrientedWideView {
  const OrientedWideBvh* bvh = nullptr;
  TriangleSet set;
  bool empty() const { return bvh == nullptr || bvh->empty(); }
};

bool intersectClosestOrientedWide(const TriangleOrientedWideView& view, Ray& ray, Hit& hit, const QueryState& state,
                                  TraversalCounters* counters = nullptr);
bool intersectAnyOrientedWide(const TriangleOrientedWideView& view, const Ray& ray, const QueryState& state,
                              TraversalCounters* counters = nullptr);

}  // namespace obvh
