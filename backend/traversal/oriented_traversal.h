// Ray queries against the oriented layouts (accel=obb, accel=hybrid): scalar stack traversal,
// nearer child first, leaves tested like every other layout's.
#pragma once

#include "bvh/oriented_bvh.h"
#include "traversal/traversal_counters.h"
#include "traversal/triangle_leaf.h"

namespace obvh {

struct TriangleOrientedView {
  const OrientedBvh* bvh = nullptr;
  TriangleSet set;
  bool empty() const { return bvh == nullptr || bvh->empty(); }
};

bool intersectClosestOriented(const TriangleOrientedView& view, Ray& ray, Hit& hit, const QueryState& state,
                              TraversalCounters* counters = nullptr);
bool intersectAnyOriented(const TriangleOrientedView& view, const Ray& ray, const QueryState& state,
                          TraversalCounters* counters = nullptr);

}  // namespace obvh
