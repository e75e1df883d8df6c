// rtcIntersect* and rtcOccluded*: validate, convert Embree's ray layouts to the backend's and back.
// Packets and streams run the single-ray kernel per active lane in this slice.
#include <embree3/rtcore.h>

#include <limits>

#include "api_error.h"
#include "scene.h"

using namespace obvh::api;

namespace {

obvh::Ray toBackendRay(const RTCRay& r) {
  obvh::Ray ray;
  ray.org = {r.org_x, r.org_y, r.org_z};
  ray.dir = {r.dir_x, r.dir_y, r.dir_z};
  ray.tnear = r.tnear;
  ray.tfar = r.tfar;
  ray.mask = r.mask;
  return ray;
}

// Writes a hit back in Embree's conventions; a miss leaves the record untouched.
bool intersectOne(const Scene& scene, const RTCIntersectContext& context, RTCRayHit& rayhit) {
  obvh::Ray ray = toBackendRay(rayhit.ray);
  obvh::Hit hit;
  if (!scene.accel().intersect(ray, hit)) return false;
  rayhit.ray.tfar = ray.tfar;
  rayhit.hit.Ng_x = hit.Ng.x;
  rayhit.hit.Ng_y = hit.Ng.y;
  rayhit.hit.Ng_z = hit.Ng.z;
  rayhit.hit.u = hit.u;
  rayhit.hit.v = hit.v;
  rayhit.hit.primID = hit.primID;
  rayhit.hit.geomID = hit.geomID;
  for (unsigned level = 0; level < RTC_MAX_INSTANCE_LEVEL_COUNT; ++level)
    rayhit.hit.instID[level] = context.instID[level];
  return true;
}

void occludedOne(const Scene& scene, RTCRay& ray) {
  if (scene.accel().occluded(toBackendRay(ray))) ray.tfar = -std::numeric_limits<float>::infinity();
}

// Validates the handles shared by every query and runs body with the committed scene.
template <typename Body>
void query(RTCScene handle, const RTCIntersectContext* context, const void* rays, Body&& body) {
  Scene* scene = Scene::from(handle);
  guarded(scene ? scene->device() : nullptr, [&] {
    requireHandle(scene);
    requireHandle(context);
    requireHandle(rays);
    scene->requireCommitted();
    body(*scene, *context);
  });
}

// Lanes whose valid entry is -1 are active, as in Embree; a null mask activates every lane.
bool laneActive(const int* valid, unsigned lane) { return valid == nullptr || valid[lane] == -1; }

void intersectLanes(const Scene& scene, const RTCIntersectContext& context, const int* valid, RTCRayHitN* packet,
                    unsigned N) {
  for (unsigned i = 0; i < N; ++i) {
    if (!laneActive(valid, i)) continue;
    RTCRayHit rayhit = rtcGetRayHitFromRayHitN(packet, N, i);
    if (!intersectOne(scene, context, rayhit)) continue;
    RTCRayN_tfar(RTCRayHitN_RayN(packet, N), N, i) = rayhit.ray.tfar;
    rtcCopyHitToHitN(RTCRayHitN_HitN(packet, N), &rayhit.hit, N, i);
  }
}

void occludedLanes(const Scene& scene, const int* valid, RTCRayN* packet, unsigned N) {
  for (unsigned i = 0; i < N; ++i) {
    if (!laneActive(valid, i)) continue;
    RTCRay ray = rtcGetRayFromRayN(packet, N, i);
    occludedOne(scene, ray);
    RTCRayN_tfar(packet, N, i) = ray.tfar;
  }
}

}  // namespace

RTC_API void rtcIntersect1(RTCScene scene, RTCIntersectContext* context, RTCRayHit* rayhit) {
  query(scene, context, rayhit, [&](const Scene& s, const RTCIntersectContext& c) { intersectOne(s, c, *rayhit); });
}

RTC_API void rtcOccluded1(RTCScene scene, RTCIntersectContext* context, RTCRay* ray) {
  query(scene, context, ray, [&](const Scene& s, const RTCIntersectContext&) { occludedOne(s, *ray); });
}

// RTCRayHit4/8/16 have exactly the RTCRayHitN layout for N = 4/8/16.
RTC_API void rtcIntersect4(const int* valid, RTCScene scene, RTCIntersectContext* context, RTCRayHit4* rayhit) {
  query(scene, context, rayhit, [&](const Scene& s, const RTCIntersectContext& c) {
    intersectLanes(s, c, valid, reinterpret_cast<RTCRayHitN*>(rayhit), 4);
  });
}

RTC_API void rtcIntersect8(const int* valid, RTCScene scene, RTCIntersectContext* context, RTCRayHit8* rayhit) {
  query(scene, context, rayhit, [&](const Scene& s, const RTCIntersectContext& c) {
    intersectLanes(s, c, valid, reinterpret_cast<RTCRayHitN*>(rayhit), 8);
  });
}

RTC_API void rtcIntersect16(const int* valid, RTCScene scene, RTCIntersectContext* context, RTCRayHit16* rayhit) {
  query(scene, context, rayhit, [&](const Scene& s, const RTCIntersectContext& c) {
    intersectLanes(s, c, valid, reinterpret_cast<RTCRayHitN*>(rayhit), 16);
  });
}

RTC_API void rtcOccluded4(const int* valid, RTCScene scene, RTCIntersectContext* context, RTCRay4* ray) {
  query(scene, context, ray, [&](const Scene& s, const RTCIntersectContext&) {
    occludedLanes(s, valid, reinterpret_cast<RTCRayN*>(ray), 4);
  });
}

RTC_API void rtcOccluded8(const int* valid, RTCScene scene, RTCIntersectContext* context, RTCRay8* ray) {
  query(scene, context, ray, [&](const Scene& s, const RTCIntersectContext&) {
    occludedLanes(s, valid, reinterpret_cast<RTCRayN*>(ray), 8);
  });
}

RTC_API void rtcOccluded16(const int* valid, RTCScene scene, RTCIntersectContext* context, RTCRay16* ray) {
  query(scene, context, ray, [&](const Scene& s, const RTCIntersectContext&) {
    occludedLanes(s, valid, reinterpret_cast<RTCRayN*>(ray), 16);
  });
}

RTC_API void rtcIntersect1M(RTCScene scene, RTCIntersectContext* context, RTCRayHit* rayhit, unsigned int M,
                            size_t byteStride) {
  query(scene, context, rayhit, [&](const Scene& s, const RTCIntersectContext& c) {
    auto* base = reinterpret_cast<unsigned char*>(rayhit);
    for (unsigned i = 0; i < M; ++i) intersectOne(s, c, *reinterpret_cast<RTCRayHit*>(base + i * byteStride));
  });
}

RTC_API void rtcIntersect1Mp(RTCScene scene, RTCIntersectContext* context, RTCRayHit** rayhit, unsigned int M) {
  query(scene, context, rayhit, [&](const Scene& s, const RTCIntersectContext& c) {
    for (unsigned i = 0; i < M; ++i)
      if (rayhit[i]) intersectOne(s, c, *rayhit[i]);
  });
}

RTC_API void rtcIntersectNM(RTCScene scene, RTCIntersectContext* context, RTCRayHitN* rayhit, unsigned int N,
                            unsigned int M, size_t byteStride) {
  query(scene, context, rayhit, [&](const Scene& s, const RTCIntersectContext& c) {
    auto* base = reinterpret_cast<unsigned char*>(rayhit);
    for (unsigned m = 0; m < M; ++m)
      intersectLanes(s, c, nullptr, reinterpret_cast<RTCRayHitN*>(base + m * byteStride), N);
  });
}

RTC_API void rtcIntersectNp(RTCScene scene, RTCIntersectContext* context, const RTCRayHitNp* rayhit, unsigned int N) {
  query(scene, context, rayhit, [&](const Scene& s, const RTCIntersectContext& c) {
    const RTCRayNp& r = rayhit->ray;
    const RTCHitNp& h = rayhit->hit;
    for (unsigned i = 0; i < N; ++i) {
      RTCRayHit one{};
      one.ray = {r.org_x[i], r.org_y[i], r.org_z[i], r.tnear[i], r.dir_x[i], r.dir_y[i], r.dir_z[i],
                 r.time ? r.time[i] : 0.f, r.tfar[i], r.mask ? r.mask[i] : 0xFFFFFFFFu, r.id ? r.id[i] : 0u,
                 r.flags ? r.flags[i] : 0u};
      if (!intersectOne(s, c, one)) continue;
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
  });
}

RTC_API void rtcOccluded1M(RTCScene scene, RTCIntersectContext* context, RTCRay* ray, unsigned int M,
                           size_t byteStride) {
  query(scene, context, ray, [&](const Scene& s, const RTCIntersectContext&) {
    auto* base = reinterpret_cast<unsigned char*>(ray);
    for (unsigned i = 0; i < M; ++i) occludedOne(s, *reinterpret_cast<RTCRay*>(base + i * byteStride));
  });
}

RTC_API void rtcOccluded1Mp(RTCScene scene, RTCIntersectContext* context, RTCRay** ray, unsigned int M) {
  query(scene, context, ray, [&](const Scene& s, const RTCIntersectContext&) {
    for (unsigned i = 0; i < M; ++i)
      if (ray[i]) occludedOne(s, *ray[i]);
  });
}

RTC_API void rtcOccludedNM(RTCScene scene, RTCIntersectContext* context, RTCRayN* ray, unsigned int N,
                           unsigned int M, size_t byteStride) {
  query(scene, context, ray, [&](const Scene& s, const RTCIntersectContext&) {
    auto* base = reinterpret_cast<unsigned char*>(ray);
    for (unsigned m = 0; m < M; ++m) occludedLanes(s, nullptr, reinterpret_cast<RTCRayN*>(base + m * byteStride), N);
  });
}

RTC_API void rtcOccludedNp(RTCScene scene, RTCIntersectContext* context, const RTCRayNp* ray, unsigned int N) {
  query(scene, context, ray, [&](const Scene& s, const RTCIntersectContext&) {
    for (unsigned i = 0; i < N; ++i) {
      RTCRay one = {ray->org_x[i], ray->org_y[i], ray->org_z[i], ray->tnear[i], ray->dir_x[i], ray->dir_y[i],
                    ray->dir_z[i], ray->time ? ray->time[i] : 0.f, ray->tfar[i],
                    ray->mask ? ray->mask[i] : 0xFFFFFFFFu, 0u, 0u};
      occludedOne(s, one);
      ray->tfar[i] = one.tfar;
    }
  });
}
