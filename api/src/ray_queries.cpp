// rtcIntersect* and rtcOccluded*: validate, convert Embree's ray layouts to the backend's and back.
// Packets and SOA streams go to the backend's packet traversal (QueryDispatch::intersectPacket), as
// do streams of single rays declared coherent (QueryDispatch::intersectStream).
#include <embree3/rtcore.h>

#include <algorithm>
#include <limits>

#include "api_error.h"
#include "query_dispatch.h"
#include "scene.h"

using namespace obvh::api;

namespace {

// Validates the handles shared by every query and runs body with a dispatch for the committed scene.
template <typename Body>
void query(RTCScene handle, RTCIntersectContext* context, const void* rays, Body&& body) {
  Scene* scene = Scene::from(handle);
  guarded(scene ? scene->device() : nullptr, [&] {
    requireHandle(scene);
    requireHandle(context);
    requireHandle(rays);
    scene->requireCommitted();
    QueryDispatch dispatch(*scene, *context);
    body(dispatch);
  });
}

// Ray i of an Np stream (RTCRayNp: one array per member; time, mask, id and flags may be absent).
RTCRay rayOfNp(const RTCRayNp& r, unsigned i) {
  return {r.org_x[i], r.org_y[i], r.org_z[i], r.tnear[i], r.dir_x[i], r.dir_y[i], r.dir_z[i], r.time ? r.time[i] : 0.f,
          r.tfar[i], r.mask ? r.mask[i] : 0xFFFFFFFFu, r.id ? r.id[i] : 0u, r.flags ? r.flags[i] : 0u};
}

// The general path of rtcIntersect1 and rtcOccluded1, kept out of line: inlined, its set-up
// (saved registers, the frame for its exception guard) was paid by every direct ray too, 9 of
// rtcIntersect1's instructions a ray.
[[gnu::noinline]] void intersectOne(RTCScene scene, RTCIntersectContext* context, RTCRayHit* rayhit) {
  query(scene, context, rayhit, [&](QueryDispatch& d) { d.intersect(*rayhit); });
}
[[gnu::noinline]] void occludedOne(RTCScene scene, RTCIntersectContext* context, RTCRay* ray) {
  query(scene, context, ray, [&](QueryDispatch& d) { d.occluded(*ray); });
}

// The general path of the packet queries, out of line for the reason intersectOne is: inlined, the
// set-up of its lambda's captures was paid by every direct packet too (14 of intersectPacket's
// instructions a coherent rtcIntersect8 packet, callgrind).
[[gnu::noinline]] void intersectPacketGeneral(const int* valid, RTCScene scene, RTCIntersectContext* context,
                                              RTCRayHitN* packet, unsigned N) {
  query(scene, context, packet, [&](QueryDispatch& d) { d.intersectPacket(valid, packet, N); });
}
[[gnu::noinline]] void occludedPacketGeneral(const int* valid, RTCScene scene, RTCIntersectContext* context,
                                             RTCRayN* packet, unsigned N) {
  query(scene, context, packet, [&](QueryDispatch& d) { d.occludedPacket(valid, packet, N); });
}

// rtcIntersect4/8/16 and rtcOccluded4/8/16: straight to the kernels when the scene allows it
// (directEntryOf), else through QueryDispatch.
void intersectPacket(const int* valid, RTCScene scene, RTCIntersectContext* context, RTCRayHitN* packet, unsigned N) {
  const Scene* s = Scene::from(scene);
  if (s && context && packet)
    if (const obvh::QueryEntry* entry = directEntryOf(*s))
      return intersectPacketDirectly(*entry, *s, *context, valid, packet, N);
  intersectPacketGeneral(valid, scene, context, packet, N);
}
void occludedPacket(const int* valid, RTCScene scene, RTCIntersectContext* context, RTCRayN* packet, unsigned N) {
  const Scene* s = Scene::from(scene);
  if (s && context && packet)
    if (const obvh::QueryEntry* entry = directEntryOf(*s)) return occludedPacketDirectly(*entry, *s, *context, valid, packet, N);
  occludedPacketGeneral(valid, scene, context, packet, N);
}

}  // namespace

RTC_API void rtcIntersect1(RTCScene scene, RTCIntersectContext* context, RTCRayHit* rayhit) {
  const Scene* s = Scene::from(scene);
  if (s && context && rayhit)
    if (const obvh::QueryEntry* entry = directEntryOf(*s)) return intersectDirectly(*entry, *s, *context, *rayhit);
  intersectOne(scene, context, rayhit);
}

RTC_API void rtcOccluded1(RTCScene scene, RTCIntersectContext* context, RTCRay* ray) {
  const Scene* s = Scene::from(scene);
  if (s && context && ray)
    if (const obvh::QueryEntry* entry = directEntryOf(*s)) return occludedDirectly(*entry, *s, *context, *ray);
  occludedOne(scene, context, ray);
}

// RTCRayHit4/8/16 have exactly the RTCRayHitN layout for N = 4/8/16.
RTC_API void rtcIntersect4(const int* valid, RTCScene scene, RTCIntersectContext* context, RTCRayHit4* rayhit) {
  intersectPacket(valid, scene, context, reinterpret_cast<RTCRayHitN*>(rayhit), 4);
}

RTC_API void rtcIntersect8(const int* valid, RTCScene scene, RTCIntersectContext* context, RTCRayHit8* rayhit) {
  intersectPacket(valid, scene, context, reinterpret_cast<RTCRayHitN*>(rayhit), 8);
}

RTC_API void rtcIntersect16(const int* valid, RTCScene scene, RTCIntersectContext* context, RTCRayHit16* rayhit) {
  intersectPacket(valid, scene, context, reinterpret_cast<RTCRayHitN*>(rayhit), 16);
}

RTC_API void rtcOccluded4(const int* valid, RTCScene scene, RTCIntersectContext* context, RTCRay4* ray) {
  occludedPacket(valid, scene, context, reinterpret_cast<RTCRayN*>(ray), 4);
}

RTC_API void rtcOccluded8(const int* valid, RTCScene scene, RTCIntersectContext* context, RTCRay8* ray) {
  occludedPacket(valid, scene, context, reinterpret_cast<RTCRayN*>(ray), 8);
}

RTC_API void rtcOccluded16(const int* valid, RTCScene scene, RTCIntersectContext* context, RTCRay16* ray) {
  occludedPacket(valid, scene, context, reinterpret_cast<RTCRayN*>(ray), 16);
}

RTC_API void rtcIntersect1M(RTCScene scene, RTCIntersectContext* context, RTCRayHit* rayhit, unsigned int M,
                            size_t byteStride) {
  query(scene, context, rayhit, [&](QueryDispatch& d) {
    auto* base = reinterpret_cast<unsigned char*>(rayhit);
    d.intersectStream(M, [&](unsigned i) { return reinterpret_cast<RTCRayHit*>(base + i * byteStride); });
  });
}

RTC_API void rtcIntersect1Mp(RTCScene scene, RTCIntersectContext* context, RTCRayHit** rayhit, unsigned int M) {
  query(scene, context, rayhit, [&](QueryDispatch& d) { d.intersectStream(M, [&](unsigned i) { return rayhit[i]; }); });
}

RTC_API void rtcIntersectNM(RTCScene scene, RTCIntersectContext* context, RTCRayHitN* rayhit, unsigned int N,
                            unsigned int M, size_t byteStride) {
  query(scene, context, rayhit, [&](QueryDispatch& d) {
    auto* base = reinterpret_cast<unsigned char*>(rayhit);
    for (unsigned m = 0; m < M; ++m)
      d.intersectPacket(nullptr, reinterpret_cast<RTCRayHitN*>(base + m * byteStride), N);
  });
}

RTC_API void rtcIntersectNp(RTCScene scene, RTCIntersectContext* context, const RTCRayHitNp* rayhit, unsigned int N) {
  query(scene, context, rayhit, [&](QueryDispatch& d) {
    const RTCRayNp& r = rayhit->ray;
    const RTCHitNp& h = rayhit->hit;
    // Taken over kStreamPacketRays at a time, so that a coherent stream is traced as packets.
    for (unsigned first = 0; first < N; first += kStreamPacketRays) {
      const unsigned count = std::min(N - first, kStreamPacketRays);
      RTCRayHit rays[kStreamPacketRays];
      for (unsigned k = 0; k < count; ++k) {
        rays[k] = RTCRayHit{};
        rays[k].ray = rayOfNp(r, first + k);
        rays[k].hit.geomID = RTC_INVALID_GEOMETRY_ID;  // stays so unless the ray hits
      }
      d.intersectStream(count, [&](unsigned k) { return &rays[k]; });
      for (unsigned k = 0; k < count; ++k) {
        const RTCRayHit& one = rays[k];
        if (one.hit.geomID == RTC_INVALID_GEOMETRY_ID) continue;
        const unsigned i = first + k;
        r.tfar[i] = one.ray.tfar;
        h.Ng_x[i] = one.hit.Ng_x;
        h.Ng_y[i] = one.hit.Ng_y;
        h.Ng_z[i] = one.hit.Ng_z;
        h.u[i] = one.hit.u;
        h.v[i] = one.hit.v;
        h.primID[i] = one.hit.primID;
        h.geomID[i] = one.hit.geomID;
        for (unsigned level = 0; level < RTC_MAX_INSTANCE_LEVEL_COUNT; ++level)
          if (h.instID[level]) h.instID[level][i] = one.hit.instID[level];
      }
    }
  });
}

RTC_API void rtcOccluded1M(RTCScene scene, RTCIntersectContext* context, RTCRay* ray, unsigned int M,
                           size_t byteStride) {
  query(scene, context, ray, [&](QueryDispatch& d) {
    auto* base = reinterpret_cast<unsigned char*>(ray);
    d.occludedStream(M, [&](unsigned i) { return reinterpret_cast<RTCRay*>(base + i * byteStride); });
  });
}

RTC_API void rtcOccluded1Mp(RTCScene scene, RTCIntersectContext* context, RTCRay** ray, unsigned int M) {
  query(scene, context, ray, [&](QueryDispatch& d) { d.occludedStream(M, [&](unsigned i) { return ray[i]; }); });
}

RTC_API void rtcOccludedNM(RTCScene scene, RTCIntersectContext* context, RTCRayN* ray, unsigned int N,
                           unsigned int M, size_t byteStride) {
  query(scene, context, ray, [&](QueryDispatch& d) {
    auto* base = reinterpret_cast<unsigned char*>(ray);
    for (unsigned m = 0; m < M; ++m) d.occludedPacket(nullptr, reinterpret_cast<RTCRayN*>(base + m * byteStride), N);
  });
}

RTC_API void rtcOccludedNp(RTCScene scene, RTCIntersectContext* context, const RTCRayNp* ray, unsigned int N) {
  query(scene, context, ray, [&](QueryDispatch& d) {
    for (unsigned first = 0; first < N; first += kStreamPacketRays) {
      const unsigned count = std::min(N - first, kStreamPacketRays);
      RTCRay rays[kStreamPacketRays];
      for (unsigned k = 0; k < count; ++k) rays[k] = rayOfNp(*ray, first + k);
      d.occludedStream(count, [&](unsigned k) { return &rays[k]; });
      for (unsigned k = 0; k < count; ++k)
        if (rays[k].tfar == -std::numeric_limits<float>::infinity()) ray->tfar[first + k] = rays[k].tfar;
    }
  });
}
