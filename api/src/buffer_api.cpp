// rtc* entry points for buffers.
#include <embree3/rtcore.h>

#include "api_error.h"
#include "buffer.h"

using namespace obvh::api;

RTC_API RTCBuffer rtcNewBuffer(RTCDevice device, size_t byteSize) {
  Device* d = Device::from(device);
  return guarded(d, RTCBuffer(nullptr), [&] { return (new Buffer(requireHandle(d), byteSize))->handle(); });
}

RTC_API RTCBuffer rtcNewSharedBuffer(RTCDevice device, void* ptr, size_t byteSize) {
  Device* d = Device::from(device);
  return guarded(d, RTCBuffer(nullptr), [&] { return (new Buffer(requireHandle(d), ptr, byteSize))->handle(); });
}

RTC_API void* rtcGetBufferData(RTCBuffer buffer) {
  Buffer* b = Buffer::from(buffer);
  return guarded(b ? b->device() : nullptr, static_cast<void*>(nullptr),
                 [&] { return static_cast<void*>(requireHandle(b)->data()); });
}

RTC_API void rtcRetainBuffer(RTCBuffer buffer) {
  Buffer* b = Buffer::from(buffer);
  guarded(b ? b->device() : nullptr, [&] { requireHandle(b)->retain(); });
}

RTC_API void rtcReleaseBuffer(RTCBuffer buffer) {
  Buffer* b = Buffer::from(buffer);
  guarded(b ? b->device() : nullptr, [&] { requireHandle(b)->release(); });
}
