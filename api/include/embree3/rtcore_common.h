// obvh: shared types of the Embree 3 API (formats, bounds, contexts, point queries).
#pragma once

#include <stddef.h>
#include <stdbool.h>
#include <sys/types.h>

#include "rtcore_config.h"

#if defined(_WIN32)
#  if defined(_M_X64)
typedef long long ssize_t;
#  else
typedef int ssize_t;
#  endif
#endif

#if defined(_WIN32) && !defined(__MINGW32__)
#  define RTC_ALIGN(...) __declspec(align(__VA_ARGS__))
#else
#  define RTC_ALIGN(...) __attribute__((aligned(__VA_ARGS__)))
#endif

#if !defined(RTC_DEPRECATED)
#  if defined(__GNUC__)
#    define RTC_DEPRECATED __attribute__((deprecated))
#  elif defined(_MSC_VER)
#    define RTC_DEPRECATED __declspec(deprecated)
#  else
#    define RTC_DEPRECATED
#  endif
#endif

#if defined(_WIN32)
#  define RTC_FORCEINLINE __forceinline
#else
#  define RTC_FORCEINLINE inline __attribute__((always_inline))
#endif

#define RTC_INVALID_GEOMETRY_ID ((unsigned int)-1)
#define RTC_MAX_TIME_STEP_COUNT 129

// Element formats: the high nibble group names the scalar type, the low digits the component count.
enum RTCFormat
{
  RTC_FORMAT_UNDEFINED = 0,

  RTC_FORMAT_UCHAR = 0x1001, RTC_FORMAT_UCHAR2, RTC_FORMAT_UCHAR3, RTC_FORMAT_UCHAR4,
  RTC_FORMAT_CHAR = 0x2001, RTC_FORMAT_CHAR2, RTC_FORMAT_CHAR3, RTC_FORMAT_CHAR4,
  RTC_FORMAT_USHORT = 0x3001, RTC_FORMAT_USHORT2, RTC_FORMAT_USHORT3, RTC_FORMAT_USHORT4,
  RTC_FORMAT_SHORT = 0x4001, RTC_FORMAT_SHORT2, RTC_FORMAT_SHORT3, RTC_FORMAT_SHORT4,
  RTC_FORMAT_UINT = 0x5001, RTC_FORMAT_UINT2, RTC_FORMAT_UINT3, RTC_FORMAT_UINT4,
  RTC_FORMAT_INT = 0x6001, RTC_FORMAT_INT2, RTC_FORMAT_INT3, RTC_FORMAT_INT4,
  RTC_FORMAT_ULLONG = 0x7001, RTC_FORMAT_ULLONG2, RTC_FORMAT_ULLONG3, RTC_FORMAT_ULLONG4,
  RTC_FORMAT_LLONG = 0x8001, RTC_FORMAT_LLONG2, RTC_FORMAT_LLONG3, RTC_FORMAT_LLONG4,

  RTC_FORMAT_FLOAT = 0x9001, RTC_FORMAT_FLOAT2, RTC_FORMAT_FLOAT3, RTC_FORMAT_FLOAT4,
  RTC_FORMAT_FLOAT5, RTC_FORMAT_FLOAT6, RTC_FORMAT_FLOAT7, RTC_FORMAT_FLOAT8,
  RTC_FORMAT_FLOAT9, RTC_FORMAT_FLOAT10, RTC_FORMAT_FLOAT11, RTC_FORMAT_FLOAT12,
  RTC_FORMAT_FLOAT13, RTC_FORMAT_FLOAT14, RTC_FORMAT_FLOAT15, RTC_FORMAT_FLOAT16,

  // Matrices: 0x91RC row major, 0x92RC column major (R rows, C columns).
  RTC_FORMAT_FLOAT2X2_ROW_MAJOR = 0x9122,
  RTC_FORMAT_FLOAT2X3_ROW_MAJOR = 0x9123,
  RTC_FORMAT_FLOAT2X4_ROW_MAJOR = 0x9124,
  RTC_FORMAT_FLOAT3X2_ROW_MAJOR = 0x9132,
  RTC_FORMAT_FLOAT3X3_ROW_MAJOR = 0x9133,
  RTC_FORMAT_FLOAT3X4_ROW_MAJOR = 0x9134,
  RTC_FORMAT_FLOAT4X2_ROW_MAJOR = 0x9142,
  RTC_FORMAT_FLOAT4X3_ROW_MAJOR = 0x9143,
  RTC_FORMAT_FLOAT4X4_ROW_MAJOR = 0x9144,
  RTC_FORMAT_FLOAT2X2_COLUMN_MAJOR = 0x9222,
  RTC_FORMAT_FLOAT2X3_COLUMN_MAJOR = 0x9223,
  RTC_FORMAT_FLOAT2X4_COLUMN_MAJOR = 0x9224,
  RTC_FORMAT_FLOAT3X2_COLUMN_MAJOR = 0x9232,
  RTC_FORMAT_FLOAT3X3_COLUMN_MAJOR = 0x9233,
  RTC_FORMAT_FLOAT3X4_COLUMN_MAJOR = 0x9234,
  RTC_FORMAT_FLOAT4X2_COLUMN_MAJOR = 0x9242,
  RTC_FORMAT_FLOAT4X3_COLUMN_MAJOR = 0x9243,
  RTC_FORMAT_FLOAT4X4_COLUMN_MAJOR = 0x9244,

  RTC_FORMAT_GRID = 0xA001
};

enum RTCBuildQuality
{
  RTC_BUILD_QUALITY_LOW = 0,
  RTC_BUILD_QUALITY_MEDIUM = 1,
  RTC_BUILD_QUALITY_HIGH = 2,
  RTC_BUILD_QUALITY_REFIT = 3,
};

struct RTC_ALIGN(16) RTCBounds
{
  float lower_x, lower_y, lower_z, align0;
  float upper_x, upper_y, upper_z, align1;
};

struct RTC_ALIGN(16) RTCLinearBounds
{
  struct RTCBounds bounds0;
  struct RTCBounds bounds1;
};

enum RTCIntersectContextFlags
{
  RTC_INTERSECT_CONTEXT_FLAG_NONE = 0,
  RTC_INTERSECT_CONTEXT_FLAG_INCOHERENT = (0 << 0),
  RTC_INTERSECT_CONTEXT_FLAG_COHERENT = (1 << 0)
};

struct RTCFilterFunctionNArguments
{
  int* valid;
  void* geometryUserPtr;
  struct RTCIntersectContext* context;
  struct RTCRayN* ray;
  struct RTCHitN* hit;
  unsigned int N;
};

typedef void (*RTCFilterFunctionN)(const struct RTCFilterFunctionNArguments* args);

struct RTCIntersectContext
{
  enum RTCIntersectContextFlags flags;
  RTCFilterFunctionN filter;
#if RTC_MAX_INSTANCE_LEVEL_COUNT > 1
  unsigned int instStackSize;
#endif
  unsigned int instID[RTC_MAX_INSTANCE_LEVEL_COUNT];
#if RTC_MIN_WIDTH
  float minWidthDistanceFactor;
#endif
};

RTC_FORCEINLINE void rtcInitIntersectContext(struct RTCIntersectContext* context)
{
  unsigned int level;
  context->flags = RTC_INTERSECT_CONTEXT_FLAG_INCOHERENT;
  context->filter = NULL;
#if RTC_MAX_INSTANCE_LEVEL_COUNT > 1
  context->instStackSize = 0;
#endif
  for (level = 0; level < RTC_MAX_INSTANCE_LEVEL_COUNT; ++level)
    context->instID[level] = RTC_INVALID_GEOMETRY_ID;
#if RTC_MIN_WIDTH
  context->minWidthDistanceFactor = 0.0f;
#endif
}

struct RTC_ALIGN(16) RTCPointQuery
{
  float x, y, z;
  float time;
  float radius;
};

struct RTC_ALIGN(16) RTCPointQuery4
{
  float x[4], y[4], z[4];
  float time[4];
  float radius[4];
};

struct RTC_ALIGN(32) RTCPointQuery8
{
  float x[8], y[8], z[8];
  float time[8];
  float radius[8];
};

struct RTC_ALIGN(64) RTCPointQuery16
{
  float x[16], y[16], z[16];
  float time[16];
  float radius[16];
};

struct RTCPointQueryN;

struct RTC_ALIGN(16) RTCPointQueryContext
{
  float world2inst[RTC_MAX_INSTANCE_LEVEL_COUNT][16];
  float inst2world[RTC_MAX_INSTANCE_LEVEL_COUNT][16];
  unsigned int instID[RTC_MAX_INSTANCE_LEVEL_COUNT];
  unsigned int instStackSize;
};

RTC_FORCEINLINE void rtcInitPointQueryContext(struct RTCPointQueryContext* context)
{
  context->instStackSize = 0;
  context->instID[0] = RTC_INVALID_GEOMETRY_ID;
}

struct RTC_ALIGN(16) RTCPointQueryFunctionArguments
{
  struct RTCPointQuery* query;
  void* userPtr;
  unsigned int primID;
  unsigned int geomID;
  struct RTCPointQueryContext* context;
  float similarityScale;
};

typedef bool (*RTCPointQueryFunction)(struct RTCPointQueryFunctionArguments* args);
