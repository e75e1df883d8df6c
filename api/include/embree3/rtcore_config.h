// obvh: Embree 3.13.5 compatible configuration header.
// The values below are ABI facts fixed by Embree 3.13.5; obvh reports the same version so that
// programs that check RTC_VERSION at compile time or at run time treat obvh as that release.
#pragma once

// Lets code (and the ABI test) tell obvh's header from Embree's.
#define OBVH_EMBREE3_HEADER 1

#define RTC_VERSION_MAJOR 3
#define RTC_VERSION_MINOR 13
#define RTC_VERSION_PATCH 5
#define RTC_VERSION 31305
#define RTC_VERSION_STRING "3.13.5"

// Debian's build uses one instance level; the layout of RTCHit and RTCIntersectContext depends on it.
#define RTC_MAX_INSTANCE_LEVEL_COUNT 1

#define EMBREE_MIN_WIDTH 0
#define RTC_MIN_WIDTH EMBREE_MIN_WIDTH

// obvh has no namespaced build; these stay empty so Embree programs that use them still compile.
#define RTC_NAMESPACE_BEGIN
#define RTC_NAMESPACE_END
#define RTC_NAMESPACE_USE

#if defined(__cplusplus)
#  define RTC_API_EXTERN_C extern "C"
#else
#  define RTC_API_EXTERN_C
#endif

#if defined(_WIN32)
#  define RTC_API_IMPORT RTC_API_EXTERN_C __declspec(dllimport)
#  define RTC_API_EXPORT RTC_API_EXTERN_C __declspec(dllexport)
#else
#  define RTC_API_IMPORT RTC_API_EXTERN_C
#  define RTC_API_EXPORT RTC_API_EXTERN_C __attribute__((visibility("default")))
#endif

// obvh's own sources define RTC_EXPORT_API so the library exports the rtc* entry points.
#if defined(RTC_EXPORT_API)
#  define RTC_API RTC_API_EXPORT
#else
#  define RTC_API RTC_API_IMPORT
#endif
