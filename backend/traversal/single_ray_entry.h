// A committed scene's single-ray queries reduced to what rtcIntersect1 and rtcOccluded1 need at
// every ray: the structure to trace and the kernels to trace it with, chosen once at commit.
// Choosing them per ray (the layout, whether its tree is empty, then the coherence hint) took
// about ten instructions of rtcIntersect1's own 63 a bunny camera ray (callgrind; Embree's
// rtcIntersect1 runs 23 of its own).
#pragma once

#include "intersect/ray.h"
#include "traversal/query_callbacks.h"

namespace obvh {

struct SingleRayEntry {
  using Closest = bool (*)(const void* target, Ray& ray, Hit& hit, const QueryState& state);
  using Any = bool (*)(const void* target, const Ray& ray, const QueryState& state);

  const void* target = nullptr;  // what the kernels trace (a layout's view, or the scene's structure)
  // Indexed by QueryState::coherent: the walk for incoherent rays, then the one for coherent rays.
  // The state passed must not count (QueryState::counters null).
  Closest closest[2] = {&missesAll, &missesAll};
  Any any[2] = {&blocksNothing, &blocksNothing};

  // coherent: state.coherent, passed by callers that know it without loading it from the state.
  bool intersect(Ray& ray, Hit& hit, const QueryState& state, bool coherent) const {
    return closest[coherent](target, ray, hit, state);
  }
  bool occluded(const Ray& ray, const QueryState& state, bool coherent) const {
    return any[coherent](target, ray, state);
  }

  // An empty structure's kernels.
  static bool missesAll(const void*, Ray&, Hit&, const QueryState&) { return false; }
  static bool blocksNothing(const void*, const Ray&, const QueryState&) { return false; }
};

}  // namespace obvh
