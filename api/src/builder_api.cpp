// The generic BVH builder API (rtcNewBVH, rtcBuildBVH); not implemented by obvh yet. The entry
// points exist so Embree programs load, and they report an error instead of pretending to work.
#include <embree3/rtcore.h>

#include "api_error.h"
#include "device.h"

using namespace obvh::api;

namespace {
constexpr const char* kNotYet = "the rtcBuildBVH builder API is not supported by obvh yet";
}

RTC_API RTCBVH rtcNewBVH(RTCDevice device) {
  Device* d = Device::from(device);
  return guarded(d, RTCBVH(nullptr), [&]() -> RTCBVH {
    requireHandle(d);
    fail(RTC_ERROR_INVALID_OPERATION, kNotYet);
  });
}

RTC_API void* rtcBuildBVH(const RTCBuildArguments*) {
  reportError(nullptr, RTC_ERROR_INVALID_OPERATION, kNotYet);
  return nullptr;
}

RTC_API void* rtcThreadLocalAlloc(RTCThreadLocalAllocator, size_t, size_t) {
  reportError(nullptr, RTC_ERROR_INVALID_OPERATION, kNotYet);
  return nullptr;
}

// No RTCBVH can exist, so a non-null handle here is not one of ours.
RTC_API void rtcRetainBVH(RTCBVH bvh) {
  reportError(nullptr, RTC_ERROR_INVALID_ARGUMENT, bvh ? kNotYet : "invalid argument: null handle");
}

RTC_API void rtcReleaseBVH(RTCBVH bvh) {
  reportError(nullptr, RTC_ERROR_INVALID_ARGUMENT, bvh ? kNotYet : "invalid argument: null handle");
}

// Exported by Embree's library without a declaration in its headers.
extern "C" __attribute__((visibility("default"))) void rtcMakeStaticBVH(RTCBVH) {
  reportError(nullptr, RTC_ERROR_INVALID_OPERATION, kNotYet);
}
