// What a ray query may need from outside the backend while it traverses: Embree's filter
// callbacks and user-geometry callbacks live in the API layer, behind this interface.
#pragma once

#include <cstdint>

#include "intersect/ray.h"
#include "traversal/traversal_counters.h"

namespace obvh {

struct QueryState;

class QueryCallbacks {
 public:
  virtual ~QueryCallbacks() = default;
  // owner: the API object of the scene that holds geomID. ray.tfar is the current segment end and
  // candidate.t-style distance is passed as t. Return false to reject the candidate.
  virtual bool acceptHit(const void* owner, const Ray& ray, const Hit& candidate, float t, bool occlusion) = 0;
  // User geometry: update ray.tfar and hit on a closer hit and return true.
  virtual bool intersectUser(const void* owner, uint32_t geomID, uint32_t primID, Ray& ray, Hit& hit,
                             const QueryState& state) = 0;
  virtual bool occludedUser(const void* owner, uint32_t geomID, uint32_t primID, Ray& ray,
                            const QueryState& state) = 0;
};

// Per-query state threaded through the (possibly two-level) traversal.
struct QueryState {
  QueryCallbacks* callbacks = nullptr;
  bool contextFilter = false;          // call the filter for every geometry (Embree's context filter)
  uint32_t instID = kInvalidId;        // the instance being traversed, written to hits
  int instanceLevel = 0;
  // When set, single-ray traversals count their box tests and leaf visits here (heatmaps); also
  // inside instances. Null on the normal query path.
  TraversalCounters* counters = nullptr;
  // The application declared the query's rays coherent (Embree's RTC_INTERSECT_CONTEXT_FLAG_COHERENT:
  // camera rays of neighbouring pixels, shadow rays to one light). The wide layouts' single rays
  // then let the branch predictor guess each next child (wide_walk.h, kPredictLanes; the oriented
  // layouts without first checking the thread's previous ray), which such rays repay and
  // incoherent ones pay for; the answers are the same either way.
  bool coherent = false;
};

}  // namespace obvh
