// Point queries (Embree's rtcPointQuery): the backend finds the primitives whose bounds overlap the
// query sphere; the API layer runs the user's callbacks on them, which may shrink the radius.
#pragma once

#include <cstdint>

#include "math/affine.h"

namespace obvh {

// The instance a point query descended through, for the callback's context.
struct PointQueryInstance {
  uint32_t geomID;
  const Affine3f* localToWorld;
  float similarityScale;  // uniform scale of world-to-instance, 0 when it is not a similarity (as Embree)
};

class PointQueryCallbacks {
 public:
  virtual ~PointQueryCallbacks() = default;
  // The current query radius in world space (callbacks may shrink it).
  virtual float radius() const = 0;
  // The query's time: where motion-blurred geometry is.
  virtual float time() const = 0;
  // Called once per primitive whose bounds overlap the query sphere; returns true when the
  // callback changed the query (for example shrank the radius).
  virtual bool visit(const void* owner, uint32_t geomID, uint32_t primID, const PointQueryInstance* instance) = 0;
};

}  // namespace obvh
