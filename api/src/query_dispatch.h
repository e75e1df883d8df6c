// The API side of a ray query: converts rays, runs Embree's filter and user-geometry callbacks
// for the backend (obvh::QueryCallbacks), and writes hits back in Embree's conventions.
#pragma once

#include <embree3/rtcore.h>

#include <algorithm>
#include <cstddef>
#include <cstring>
#include <limits>
#include <type_traits>

#include "geometry.h"
#include "memory/uninitialized_array.h"
#include "scene.h"
#include "traversal/query_callbacks.h"
#include "traversal_statistics_state.h"

namespace obvh::api {

// Hit repeats RTCHit's fields in RTCHit's order: one 32-byte copy hands a hit over (field by
// field, with geomID and primID in the other order, it took 11 instructions).
static_assert(std::is_trivially_copyable_v<Hit> && sizeof(Hit) == sizeof(RTCHit) &&
              offsetof(Hit, Ng) == offsetof(RTCHit, Ng_x) && offsetof(Hit, u) == offsetof(RTCHit, u) &&
              offsetof(Hit, v) == offsetof(RTCHit, v) && offsetof(Hit, primID) == offsetof(RTCHit, primID) &&
              offsetof(Hit, geomID) == offsetof(RTCHit, geomID) && offsetof(Hit, instID) == offsetof(RTCHit, instID) &&
              RTC_MAX_INSTANCE_LEVEL_COUNT == 1);

inline RTCHit embreeHit(const Hit& hit) {
  RTCHit out;
  std::memcpy(static_cast<void*>(&out), &hit, sizeof out);
  return out;
}

// Ray repeats RTCRay's first fields in RTCRay's order: one 40-byte copy takes a ray over (the
// field-by-field conversion cost about 20 instructions a ray).
static_assert(std::is_trivially_copyable_v<Ray> && sizeof(Ray) == offsetof(RTCRay, id) &&
              offsetof(Ray, org) == offsetof(RTCRay, org_x) && offsetof(Ray, tnear) == offsetof(RTCRay, tnear) &&
              offsetof(Ray, dir) == offsetof(RTCRay, dir_x) && offsetof(Ray, time) == offsetof(RTCRay, time) &&
              offsetof(Ray, tfar) == offsetof(RTCRay, tfar) && offsetof(Ray, mask) == offsetof(RTCRay, mask) &&
              sizeof(Vec3f) == 3 * sizeof(float));

inline Ray backendRay(const RTCRay& r, bool masksOn) {
  Ray ray;
  std::memcpy(static_cast<void*>(&ray), &r, sizeof ray);
  if (!masksOn) ray.mask = 0xFFFFFFFFu;
  return ray;
}

// Embree's coherence hint (rtcInitIntersectContext leaves it off); see QueryState::coherent.
inline bool declaresCoherentRays(const RTCIntersectContext& context) {
  return (context.flags & RTC_INTERSECT_CONTEXT_FLAG_COHERENT) != 0;
}

// Single rays against a committed scene that is one wide triangle tree with nothing to call back
// (no filters, user geometry or instances) while nobody counts traversal steps go straight to the
// kernels, without QueryDispatch's set-up: that set-up, spread over five calls, was about a third
// of the instructions of a ray that misses the scene. The answers are the same. Returns the
// scene's entry (Scene::directEntry), or null when its rays take the general path.
inline const QueryEntry* directEntryOf(const Scene& scene) {
  const QueryEntry* entry = scene.directEntry();
  return entry && !anyThreadCounting() ? entry : nullptr;
}

// The query state of a direct ray: one of two constants for a context outside instances (every
// application's own rays), indexed by the coherence hint, else made in `own`. The six stores of a
// state made for every ray were a tenth of rtcIntersect1's own instructions.
inline constexpr QueryState kDirectRayStates[2] = {QueryState{}, [] {
                                                     QueryState state{};
                                                     state.coherent = true;
                                                     return state;
                                                   }()};
// own: storage left unset until it is needed (made up front, its defaults were stored for every ray).
inline const QueryState& directQueryState(const RTCIntersectContext& context, UninitializedArray<QueryState, 1>& own) {
  const bool coherent = declaresCoherentRays(context);
  if (context.instID[0] == RTC_INVALID_GEOMETRY_ID) return kDirectRayStates[coherent];
  own[0] = QueryState{};
  own[0].instID = context.instID[0];
  own[0].coherent = coherent;
  return own[0];
}

inline void intersectDirectly(const QueryEntry& entry, const Scene& scene, const RTCIntersectContext& context,
                              RTCRayHit& rayhit) {
  Ray ray = backendRay(rayhit.ray, scene.rayMasks());
  // Left unset: the kernels write the whole hit when they find one, and it is read only then (its
  // defaults cost five instructions a ray, most rays of a camera missing).
  UninitializedArray<Hit, 1> hit;
  UninitializedArray<QueryState, 1> own;
  if (!entry.intersect(ray, hit[0], directQueryState(context, own), declaresCoherentRays(context))) return;
  rayhit.ray.tfar = ray.tfar;
  rayhit.hit = embreeHit(hit[0]);
}

inline void occludedDirectly(const QueryEntry& entry, const Scene& scene, const RTCIntersectContext& context,
                             RTCRay& rtcRay) {
  UninitializedArray<QueryState, 1> own;
  if (entry.occluded(backendRay(rtcRay, scene.rayMasks()), directQueryState(context, own), declaresCoherentRays(context)))
    rtcRay.tfar = -std::numeric_limits<float>::infinity();
}

// Packets (Embree's SOA layout, N lanes, lane i active when valid[i] == -1 or valid is null) past
// QueryDispatch, traced by the entry's packet kernels in groups of kMaxPacketSize lanes: for a
// coherent rtcIntersect8 packet QueryDispatch's set-up and dispatch were about a twentieth of its
// instructions (callgrind, bunny).
void intersectPacketDirectly(const QueryEntry& entry, const Scene& scene, const RTCIntersectContext& context,
                             const int* valid, RTCRayHitN* packet, unsigned N);
void occludedPacketDirectly(const QueryEntry& entry, const Scene& scene, const RTCIntersectContext& context,
                            const int* valid, RTCRayN* packet, unsigned N);

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
  // Streams of single rays (rtcIntersect1M/1Mp/Np, rtcOccluded1M/1Mp/Np): rayAt(i) is ray i of
  // count, or null for a lane to skip (1Mp). Declared coherent and with no callback to observe the order,
  // they are traced as packets of consecutive rays, as Embree's coherent streams are; else one by
  // one.
  template <typename RayHitAt>
  void intersectStream(unsigned count, RayHitAt&& rayAt);
  template <typename RayAt>
  void occludedStream(unsigned count, RayAt&& rayAt);

  bool acceptHit(const void* owner, const Ray& ray, const Hit& candidate, float t, bool occlusion) override;
  bool intersectUser(const void* owner, uint32_t geomID, uint32_t primID, Ray& ray, Hit& hit,
                     const QueryState& state) override;
  bool occludedUser(const void* owner, uint32_t geomID, uint32_t primID, Ray& ray, const QueryState& state) override;

  // Runs the geometry's filter and then the context filter (when enabled) on filterArgs.
  void runFilters(const Geometry& geometry, const RTCFilterFunctionNArguments* filterArgs, bool occlusion) const;

 private:
  RTCRay embreeRay(const Ray& ray, float tfar) const;
  template <typename Application, typename RayAt, typename Trace>
  void traceStreamInPackets(unsigned count, RayAt&& rayAt, const PacketGate* gate, Trace&& trace) const;

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

// How many consecutive rays of a coherent stream travel as one packet: eight-wide nodes test them
// as one lane group.
constexpr unsigned kStreamPacketRays = 8;
static_assert(kStreamPacketRays <= unsigned(kMaxPacketSize));

// Whether the CPU gathers lanes eight at a time (it has AVX2): whole packets of a stream
// (gatherStreamLanesByEights), and the lanes of rtcIntersect8/16 and rtcOccluded8/16.
bool cpuGathersInEights();
// The live lanes of eight application rays (segment not empty, not turned away by the gate: the
// box around the structure's root children, packet_gate.h), as the rtcIntersect8 gather takes
// them; their backend rays are written to rays[0..8). The gate tests the rays as lanes of one
// transposed load of their leading fields. Tested on the backend rays once written, the gate made
// coherent streams 0.96-1.00x as fast: those loads wait on the rays' field-by-field stores.
uint32_t gatherStreamLanesByEights(const RTCRay* const application[8], bool masksOn, const PacketGate& gate,
                                   Ray* rays);

inline const RTCRay& embreeRayOf(const RTCRayHit& rayhit) { return rayhit.ray; }
inline const RTCRay& embreeRayOf(const RTCRay& ray) { return ray; }

// Gathers the stream's rays kStreamPacketRays at a time into backend rays and hands each packet to
// trace(rays, live, application): application[k] is the application's ray of lane k, live the
// lanes to trace. Null entries and empty segments (tnear > tfar, which can report nothing) are
// left out, as gatherLiveLanes leaves them out of packets, and so are the rays that the gate
// (null: none) turns away, for whole packets of rays on CPUs with AVX2.
template <typename Application, typename RayAt, typename Trace>
void QueryDispatch::traceStreamInPackets(unsigned count, RayAt&& rayAt, const PacketGate* gate, Trace&& trace) const {
  static_assert(kStreamPacketRays == 8, "gatherStreamLanesByEights takes packets of eight");
  static const bool inEights = cpuGathersInEights();
  for (unsigned first = 0; first < count; first += kStreamPacketRays) {
    const unsigned lanes = std::min(count - first, kStreamPacketRays);
    UninitializedArray<Ray, kMaxPacketSize> rays;  // only the live lanes are written and read
    Application* application[kStreamPacketRays] = {};
    bool whole = lanes == kStreamPacketRays;
    for (unsigned k = 0; k < lanes; ++k) whole &= (application[k] = rayAt(first + k)) != nullptr;
    uint32_t live = 0;
    if (gate != nullptr && whole && inEights) {
      const RTCRay* embreeRays[kStreamPacketRays];
      for (unsigned k = 0; k < kStreamPacketRays; ++k) embreeRays[k] = &embreeRayOf(*application[k]);
      live = gatherStreamLanesByEights(embreeRays, masksOn_, *gate, rays.data());
      if (live != 0) trace(rays.data(), live, application);
      continue;
    }
    for (unsigned k = 0; k < lanes; ++k) {
      if (!application[k]) continue;
      const RTCRay& ray = embreeRayOf(*application[k]);
      if (ray.tnear > ray.tfar) continue;
      rays[k] = backendRay(ray, masksOn_);
      live |= 1u << k;
    }
    if (live != 0) trace(rays.data(), live, application);
  }
}

template <typename RayHitAt>
void QueryDispatch::intersectStream(unsigned count, RayHitAt&& rayAt) {
  if (!state_.coherent || state_.callbacks) {
    for (unsigned i = 0; i < count; ++i)
      if (RTCRayHit* rayhit = rayAt(i)) intersect(*rayhit);
    return;
  }
  // The structure's box, where the scene's rays may go straight to the kernels (directEntryOf):
  // most of a camera's rays over one object miss it, as they do in packets.
  const QueryEntry* entry = directEntryOf(scene_);
  const PacketGate* gate = entry != nullptr ? &entry->packetGate : nullptr;
  traceStreamInPackets<RTCRayHit>(count, rayAt, gate, [&](Ray* rays, uint32_t live, RTCRayHit* const* application) {
    UninitializedArray<Hit, kMaxPacketSize> hits;
    for (uint32_t found = scene_.accel().intersectPacket(rays, hits.data(), live, state_); found; found &= found - 1) {
      const unsigned k = unsigned(__builtin_ctz(found));
      application[k]->ray.tfar = rays[k].tfar;
      application[k]->hit = embreeHit(hits[k]);
    }
  });
}

template <typename RayAt>
void QueryDispatch::occludedStream(unsigned count, RayAt&& rayAt) {
  if (!state_.coherent || state_.callbacks) {
    for (unsigned i = 0; i < count; ++i)
      if (RTCRay* ray = rayAt(i)) occluded(*ray);
    return;
  }
  // No gate, as for occlusion packets (occludedInLaneGroups).
  traceStreamInPackets<RTCRay>(count, rayAt, nullptr, [&](const Ray* rays, uint32_t live, RTCRay* const* application) {
    for (uint32_t blocked = scene_.accel().occludedPacket(rays, live, state_); blocked; blocked &= blocked - 1)
      application[__builtin_ctz(blocked)]->tfar = -std::numeric_limits<float>::infinity();
  });
}

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
