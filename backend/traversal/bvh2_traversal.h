// Ray queries against a binary triangle BVH (the scalar reference layout, accel=bvh2).
#pragma once

#include "bvh/binary_bvh.h"
#include "traversal/traversal_counters.h"
#include "traversal/triangle_leaf.h"

namespace obvh {

struct TriangleBvhView {
  const Bvh2Node* nodes = nullptr;
  TriangleSet set;
  bool empty() const { return nodes == nullptr; }
};

// Closest hit in (ray.tnear, ray.tfar]; on a hit updates ray.tfar and hit and returns true.
bool intersectClosest(const TriangleBvhView& bvh, Ray& ray, Hit& hit, const QueryState& state,
                      TraversalCounters* counters = nullptr);

// Any hit in (ray.tnear, ray.tfar] that the filters accept.
bool intersectAny(const TriangleBvhView& bvh, const Ray& ray, const QueryState& state,
                  TraversalCounters* counters = nullptr);

}  // namespace obvh
