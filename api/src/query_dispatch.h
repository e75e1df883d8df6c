// The API side of a ray query: converts rays, runs Embree's filter and user-geometry callbacks
// for the backend (obvh::QueryCallbacks), and writes hits back in Embree's conventions.
#pragma once

#include <embree3/rtcore.h>

#include "geometry.h"
#include "scene.h"
#include "traversal/query_callbacks.h"

namespace obvh::api {

class QueryDispatch final : public QueryCallbacks {
 public:
  QueryDispatch(const Scene& scene, RTCIntersectContext& context);

  // Single-ray queries on Embree's structs; true on a hit.
  bool intersect(RTCRayHit& rayhit);
  bool occluded(RTCRay& ray);
  // Packets (Embree's SOA layout, N lanes, lane i active when valid[i] == -1 or valid is null).
  // Traced as backend packets when no callback can observe the order of the lanes, else lane by lane.
  void intersectPacket(const int* valid, RTCRayHitN* packet, unsigned N);
  void occludedPacket(const int* valid, RTCRayN* packet, unsigned N);

  bool acceptHit(const void* owner, const Ray& ray, const Hit& candidate, float t, bool occlusion) override;
  bool intersectUser(const void* owner, uint32_t geomID, uint32_t primID, Ray& ray, Hit& hit,
                     const QueryState& state) override;
  bool occludedUser(const void* owner, uint32_t geomID, uint32_t primID, Ray& ray, const QueryState& state) override;

  // Runs the geometry's filter and then the context filter (when enabled) on filterArgs.
  void runFilters(const Geometry& geometry, const RTCFilterFunctionNArguments* filterArgs, bool occlusion) const;

 private:
  RTCRay embreeRay(const Ray& ray, float tfar) const;

  // The members UserIntersectArguments and UserOccludedArguments share (one ray, N = 1).
  template <typename Arguments>
  void fillUserArguments(Arguments& args, int* valid, const Geometry& geometry, uint32_t geomID,
                         uint32_t primID) const {
    args.valid = valid;
    args.geometryUserPtr = geometry.userData();
    args.primID = primID;
    args.context = &context_;
    args.N = 1;
    args.geomID = geomID;
    args.dispatch = this;
    args.geometry = &geometry;
  }

  const Scene& scene_;
  RTCIntersectContext& context_;
  const RTCRay* original_ = nullptr;  // the application's ray being traced (id, flags, time)
  QueryState state_;
  bool masksOn_;
};

// What obvh passes as RTCIntersectFunctionNArguments / RTCOccludedFunctionNArguments: Embree's
// struct followed by what rtcFilterIntersection / rtcFilterOcclusion need to find the filters.
struct UserIntersectArguments : RTCIntersectFunctionNArguments {
  const QueryDispatch* dispatch;
  const Geometry* geometry;
};
struct UserOccludedArguments : RTCOccludedFunctionNArguments {
  const QueryDispatch* dispatch;
  const Geometry* geometry;
};

}  // namespace obvh::api
