// obvh: ray and hit layouts (single, SOA packets of 4/8/16, pointer streams, generic N).
#pragma once

#include "rtcore_common.h"

struct RTC_ALIGN(16) RTCRay
{
  float org_x, org_y, org_z;
  float tnear;            // the segment starts after tnear (exclusive)
  float dir_x, dir_y, dir_z;
  float time;
  float tfar;             // the segment ends at tfar (inclusive); set to the hit distance
  unsigned int mask;
  unsigned int id;
  unsigned int flags;
};

struct RTC_ALIGN(16) RTCHit
{
  float Ng_x, Ng_y, Ng_z; // unnormalized geometry normal
  float u, v;             // barycentric coordinates of the hit
  unsigned int primID;
  unsigned int geomID;
  unsigned int instID[RTC_MAX_INSTANCE_LEVEL_COUNT];
};

struct RTCRayHit
{
  struct RTCRay ray;
  struct RTCHit hit;
};

// Packets are structures of arrays; the member order is the same as in the single-ray structs.
#define OBVH_DEFINE_RAY_PACKET(W, ALIGNMENT)                                  \
  struct RTC_ALIGN(ALIGNMENT) RTCRay##W                                       \
  {                                                                           \
    float org_x[W], org_y[W], org_z[W];                                       \
    float tnear[W];                                                           \
    float dir_x[W], dir_y[W], dir_z[W];                                       \
    float time[W];                                                            \
    float tfar[W];                                                            \
    unsigned int mask[W];                                                     \
    unsigned int id[W];                                                       \
    unsigned int flags[W];                                                    \
  };                                                                          \
  struct RTC_ALIGN(ALIGNMENT) RTCHit##W                                       \
  {                                                                           \
    float Ng_x[W], Ng_y[W], Ng_z[W];                                          \
    float u[W], v[W];                                                         \
    unsigned int primID[W];                                                   \
    unsigned int geomID[W];                                                   \
    unsigned int instID[RTC_MAX_INSTANCE_LEVEL_COUNT][W];                     \
  };                                                                          \
  struct RTCRayHit##W                                                         \
  {                                                                           \
    struct RTCRay##W ray;                                                     \
    struct RTCHit##W hit;                                                     \
  };

OBVH_DEFINE_RAY_PACKET(4, 16)
OBVH_DEFINE_RAY_PACKET(8, 32)
OBVH_DEFINE_RAY_PACKET(16, 64)

#undef OBVH_DEFINE_RAY_PACKET

// Stream of N rays given as one pointer per member array.
struct RTCRayNp
{
  float* org_x;
  float* org_y;
  float* org_z;
  float* tnear;
  float* dir_x;
  float* dir_y;
  float* dir_z;
  float* time;
  float* tfar;
  unsigned int* mask;
  unsigned int* id;
  unsigned int* flags;
};

struct RTCHitNp
{
  float* Ng_x;
  float* Ng_y;
  float* Ng_z;
  float* u;
  float* v;
  unsigned int* primID;
  unsigned int* geomID;
  unsigned int* instID[RTC_MAX_INSTANCE_LEVEL_COUNT];
};

struct RTCRayHitNp
{
  struct RTCRayNp ray;
  struct RTCHitNp hit;
};

// Opaque packets of run-time width N; members are reached with the accessors below.
struct RTCRayN;
struct RTCHitN;
struct RTCRayHitN;

#if defined(__cplusplus)

#define OBVH_RAYN_FLOAT(NAME, ROW)                                                               \
  RTC_FORCEINLINE float& RTCRayN_##NAME(RTCRayN* ray, unsigned int N, unsigned int i)           \
  { return ((float*)ray)[(ROW) * N + i]; }
#define OBVH_RAYN_UINT(NAME, ROW)                                                                \
  RTC_FORCEINLINE unsigned int& RTCRayN_##NAME(RTCRayN* ray, unsigned int N, unsigned int i)    \
  { return ((unsigned int*)ray)[(ROW) * N + i]; }
#define OBVH_HITN_FLOAT(NAME, ROW)                                                               \
  RTC_FORCEINLINE float& RTCHitN_##NAME(RTCHitN* hit, unsigned int N, unsigned int i)           \
  { return ((float*)hit)[(ROW) * N + i]; }
#define OBVH_HITN_UINT(NAME, ROW)                                                                \
  RTC_FORCEINLINE unsigned int& RTCHitN_##NAME(RTCHitN* hit, unsigned int N, unsigned int i)    \
  { return ((unsigned int*)hit)[(ROW) * N + i]; }

OBVH_RAYN_FLOAT(org_x, 0)
OBVH_RAYN_FLOAT(org_y, 1)
OBVH_RAYN_FLOAT(org_z, 2)
OBVH_RAYN_FLOAT(tnear, 3)
OBVH_RAYN_FLOAT(dir_x, 4)
OBVH_RAYN_FLOAT(dir_y, 5)
OBVH_RAYN_FLOAT(dir_z, 6)
OBVH_RAYN_FLOAT(time, 7)
OBVH_RAYN_FLOAT(tfar, 8)
OBVH_RAYN_UINT(mask, 9)
OBVH_RAYN_UINT(id, 10)
OBVH_RAYN_UINT(flags, 11)

OBVH_HITN_FLOAT(Ng_x, 0)
OBVH_HITN_FLOAT(Ng_y, 1)
OBVH_HITN_FLOAT(Ng_z, 2)
OBVH_HITN_FLOAT(u, 3)
OBVH_HITN_FLOAT(v, 4)
OBVH_HITN_UINT(primID, 5)
OBVH_HITN_UINT(geomID, 6)

#undef OBVH_RAYN_FLOAT
#undef OBVH_RAYN_UINT
#undef OBVH_HITN_FLOAT
#undef OBVH_HITN_UINT

RTC_FORCEINLINE unsigned int& RTCHitN_instID(RTCHitN* hit, unsigned int N, unsigned int i, unsigned int level)
{
  return ((unsigned int*)hit)[7 * N + level * N + i];
}

// The hit part of an RTCRayHitN starts after the twelve ray members.
RTC_FORCEINLINE RTCRayN* RTCRayHitN_RayN(RTCRayHitN* rayhit, unsigned int N)
{
  (void)N;
  return (RTCRayN*)rayhit;
}

RTC_FORCEINLINE RTCHitN* RTCRayHitN_HitN(RTCRayHitN* rayhit, unsigned int N)
{
  return (RTCHitN*)&((float*)rayhit)[12 * N];
}

template <int N>
struct RTCRayNt
{
  float org_x[N], org_y[N], org_z[N];
  float tnear[N];
  float dir_x[N], dir_y[N], dir_z[N];
  float time[N];
  float tfar[N];
  unsigned int mask[N];
  unsigned int id[N];
  unsigned int flags[N];
};

template <int N>
struct RTCHitNt
{
  float Ng_x[N], Ng_y[N], Ng_z[N];
  float u[N], v[N];
  unsigned int primID[N];
  unsigned int geomID[N];
  unsigned int instID[RTC_MAX_INSTANCE_LEVEL_COUNT][N];
};

template <int N>
struct RTCRayHitNt
{
  RTCRayNt<N> ray;
  RTCHitNt<N> hit;
};

RTC_FORCEINLINE RTCRay rtcGetRayFromRayN(RTCRayN* rayN, unsigned int N, unsigned int i)
{
  RTCRay ray;
  ray.org_x = RTCRayN_org_x(rayN, N, i);
  ray.org_y = RTCRayN_org_y(rayN, N, i);
  ray.org_z = RTCRayN_org_z(rayN, N, i);
  ray.tnear = RTCRayN_tnear(rayN, N, i);
  ray.dir_x = RTCRayN_dir_x(rayN, N, i);
  ray.dir_y = RTCRayN_dir_y(rayN, N, i);
  ray.dir_z = RTCRayN_dir_z(rayN, N, i);
  ray.time = RTCRayN_time(rayN, N, i);
  ray.tfar = RTCRayN_tfar(rayN, N, i);
  ray.mask = RTCRayN_mask(rayN, N, i);
  ray.id = RTCRayN_id(rayN, N, i);
  ray.flags = RTCRayN_flags(rayN, N, i);
  return ray;
}

RTC_FORCEINLINE RTCHit rtcGetHitFromHitN(RTCHitN* hitN, unsigned int N, unsigned int i)
{
  RTCHit hit;
  hit.Ng_x = RTCHitN_Ng_x(hitN, N, i);
  hit.Ng_y = RTCHitN_Ng_y(hitN, N, i);
  hit.Ng_z = RTCHitN_Ng_z(hitN, N, i);
  hit.u = RTCHitN_u(hitN, N, i);
  hit.v = RTCHitN_v(hitN, N, i);
  hit.primID = RTCHitN_primID(hitN, N, i);
  hit.geomID = RTCHitN_geomID(hitN, N, i);
  for (unsigned int level = 0; level < RTC_MAX_INSTANCE_LEVEL_COUNT; level++)
    hit.instID[level] = RTCHitN_instID(hitN, N, i, level);
  return hit;
}

RTC_FORCEINLINE void rtcCopyHitToHitN(RTCHitN* hitN, const RTCHit* hit, unsigned int N, unsigned int i)
{
  RTCHitN_Ng_x(hitN, N, i) = hit->Ng_x;
  RTCHitN_Ng_y(hitN, N, i) = hit->Ng_y;
  RTCHitN_Ng_z(hitN, N, i) = hit->Ng_z;
  RTCHitN_u(hitN, N, i) = hit->u;
  RTCHitN_v(hitN, N, i) = hit->v;
  RTCHitN_primID(hitN, N, i) = hit->primID;
  RTCHitN_geomID(hitN, N, i) = hit->geomID;
  for (unsigned int level = 0; level < RTC_MAX_INSTANCE_LEVEL_COUNT; level++)
    RTCHitN_instID(hitN, N, i, level) = hit->instID[level];
}

RTC_FORCEINLINE RTCRayHit rtcGetRayHitFromRayHitN(RTCRayHitN* rayhitN, unsigned int N, unsigned int i)
{
  RTCRayHit rayhit;
  rayhit.ray = rtcGetRayFromRayN(RTCRayHitN_RayN(rayhitN, N), N, i);
  rayhit.hit = rtcGetHitFromHitN(RTCRayHitN_HitN(rayhitN, N), N, i);
  return rayhit;
}

#endif
