// obvh: scenes, commit, bounds, point queries and ray queries.
#pragma once

#include "rtcore_device.h"

struct RTCRayHit;
struct RTCRayHit4;
struct RTCRayHit8;
struct RTCRayHit16;
struct RTCRayHitNp;

enum RTCSceneFlags
{
  RTC_SCENE_FLAG_NONE = 0,
  RTC_SCENE_FLAG_DYNAMIC = (1 << 0),
  RTC_SCENE_FLAG_COMPACT = (1 << 1),
  RTC_SCENE_FLAG_ROBUST = (1 << 2),
  RTC_SCENE_FLAG_CONTEXT_FILTER_FUNCTION = (1 << 3)
};

RTC_API RTCScene rtcNewScene(RTCDevice device);
// Increments the returned device's reference count.
RTC_API RTCDevice rtcGetSceneDevice(RTCScene hscene);
RTC_API void rtcRetainScene(RTCScene scene);
RTC_API void rtcReleaseScene(RTCScene scene);

RTC_API unsigned int rtcAttachGeometry(RTCScene scene, RTCGeometry geometry);
RTC_API void rtcAttachGeometryByID(RTCScene scene, RTCGeometry geometry, unsigned int geomID);
RTC_API void rtcDetachGeometry(RTCScene scene, unsigned int geomID);
RTC_API RTCGeometry rtcGetGeometry(RTCScene scene, unsigned int geomID);
RTC_API RTCGeometry rtcGetGeometryThreadSafe(RTCScene scene, unsigned int geomID);

RTC_API void rtcCommitScene(RTCScene scene);
RTC_API void rtcJoinCommitScene(RTCScene scene);

typedef bool (*RTCProgressMonitorFunction)(void* ptr, double n);
RTC_API void rtcSetSceneProgressMonitorFunction(RTCScene scene, RTCProgressMonitorFunction progress, void* ptr);
RTC_API void rtcSetSceneBuildQuality(RTCScene scene, enum RTCBuildQuality quality);
RTC_API void rtcSetSceneFlags(RTCScene scene, enum RTCSceneFlags flags);
RTC_API enum RTCSceneFlags rtcGetSceneFlags(RTCScene scene);
RTC_API void rtcGetSceneBounds(RTCScene scene, struct RTCBounds* bounds_o);
RTC_API void rtcGetSceneLinearBounds(RTCScene scene, struct RTCLinearBounds* bounds_o);

RTC_API bool rtcPointQuery(RTCScene scene, struct RTCPointQuery* query, struct RTCPointQueryContext* context,
                           RTCPointQueryFunction queryFunc, void* userPtr);
RTC_API bool rtcPointQuery4(const int* valid, RTCScene scene, struct RTCPointQuery4* query,
                            struct RTCPointQueryContext* context, RTCPointQueryFunction queryFunc, void** userPtr);
RTC_API bool rtcPointQuery8(const int* valid, RTCScene scene, struct RTCPointQuery8* query,
                            struct RTCPointQueryContext* context, RTCPointQueryFunction queryFunc, void** userPtr);
RTC_API bool rtcPointQuery16(const int* valid, RTCScene scene, struct RTCPointQuery16* query,
                             struct RTCPointQueryContext* context, RTCPointQueryFunction queryFunc, void** userPtr);

RTC_API void rtcIntersect1(RTCScene scene, struct RTCIntersectContext* context, struct RTCRayHit* rayhit);
RTC_API void rtcIntersect4(const int* valid, RTCScene scene, struct RTCIntersectContext* context,
                           struct RTCRayHit4* rayhit);
RTC_API void rtcIntersect8(const int* valid, RTCScene scene, struct RTCIntersectContext* context,
                           struct RTCRayHit8* rayhit);
RTC_API void rtcIntersect16(const int* valid, RTCScene scene, struct RTCIntersectContext* context,
                            struct RTCRayHit16* rayhit);
RTC_API void rtcIntersect1M(RTCScene scene, struct RTCIntersectContext* context, struct RTCRayHit* rayhit,
                            unsigned int M, size_t byteStride);
RTC_API void rtcIntersect1Mp(RTCScene scene, struct RTCIntersectContext* context, struct RTCRayHit** rayhit,
                             unsigned int M);
RTC_API void rtcIntersectNM(RTCScene scene, struct RTCIntersectContext* context, struct RTCRayHitN* rayhit,
                            unsigned int N, unsigned int M, size_t byteStride);
RTC_API void rtcIntersectNp(RTCScene scene, struct RTCIntersectContext* context,
                            const struct RTCRayHitNp* rayhit, unsigned int N);

// On a hit, the occlusion queries set the ray's tfar to -infinity.
RTC_API void rtcOccluded1(RTCScene scene, struct RTCIntersectContext* context, struct RTCRay* ray);
RTC_API void rtcOccluded4(const int* valid, RTCScene scene, struct RTCIntersectContext* context,
                          struct RTCRay4* ray);
RTC_API void rtcOccluded8(const int* valid, RTCScene scene, struct RTCIntersectContext* context,
                          struct RTCRay8* ray);
RTC_API void rtcOccluded16(const int* valid, RTCScene scene, struct RTCIntersectContext* context,
                           struct RTCRay16* ray);
RTC_API void rtcOccluded1M(RTCScene scene, struct RTCIntersectContext* context, struct RTCRay* ray,
                           unsigned int M, size_t byteStride);
RTC_API void rtcOccluded1Mp(RTCScene scene, struct RTCIntersectContext* context, struct RTCRay** ray,
                            unsigned int M);
RTC_API void rtcOccludedNM(RTCScene scene, struct RTCIntersectContext* context, struct RTCRayN* ray,
                           unsigned int N, unsigned int M, size_t byteStride);
RTC_API void rtcOccludedNp(RTCScene scene, struct RTCIntersectContext* context, const struct RTCRayNp* ray,
                           unsigned int N);

struct RTCCollision
{
  unsigned int geomID0;
  unsigned int primID0;
  unsigned int geomID1;
  unsigned int primID1;
};

typedef void (*RTCCollideFunc)(void* userPtr, struct RTCCollision* collisions, unsigned int num_collisions);
RTC_API void rtcCollide(RTCScene scene0, RTCScene scene1, RTCCollideFunc callback, void* userPtr);

#if defined(__cplusplus)
inline RTCSceneFlags operator|(RTCSceneFlags a, RTCSceneFlags b)
{
  return (RTCSceneFlags)((size_t)a | (size_t)b);
}
#endif
