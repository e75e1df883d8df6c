// rtc* entry points for devices.
#include <embree3/rtcore.h>

#include "api_error.h"
#include "enum_bits.h"
#include "device.h"

using namespace obvh::api;

namespace {

ssize_t queryProperty(const Device& device, int prop) {
  switch (prop) {
    case RTC_DEVICE_PROPERTY_VERSION: return RTC_VERSION;
    case RTC_DEVICE_PROPERTY_VERSION_MAJOR: return RTC_VERSION_MAJOR;
    case RTC_DEVICE_PROPERTY_VERSION_MINOR: return RTC_VERSION_MINOR;
    case RTC_DEVICE_PROPERTY_VERSION_PATCH: return RTC_VERSION_PATCH;
    // Packets and streams are served through the single-ray kernel; they are functionally
    // supported, which is what these properties promise.
    case RTC_DEVICE_PROPERTY_NATIVE_RAY4_SUPPORTED: return 1;
    case RTC_DEVICE_PROPERTY_NATIVE_RAY8_SUPPORTED: return 1;
    case RTC_DEVICE_PROPERTY_NATIVE_RAY16_SUPPORTED: return 0;  // as Debian's build reports
    case RTC_DEVICE_PROPERTY_RAY_STREAM_SUPPORTED: return 1;
    case RTC_DEVICE_PROPERTY_BACKFACE_CULLING_CURVES_ENABLED: return 0;
    case RTC_DEVICE_PROPERTY_RAY_MASK_SUPPORTED: return device.config().rayMasks ? 1 : 0;
    case RTC_DEVICE_PROPERTY_BACKFACE_CULLING_ENABLED: return 0;
    // Of curves and points obvh has flat linear curves and sphere points only: these two
    // properties promise every curve and point type, so they stay 0.
    case RTC_DEVICE_PROPERTY_FILTER_FUNCTION_SUPPORTED: return 1;
    case RTC_DEVICE_PROPERTY_IGNORE_INVALID_RAYS_ENABLED: return 0;
    case RTC_DEVICE_PROPERTY_COMPACT_POLYS_ENABLED: return 0;
    case RTC_DEVICE_PROPERTY_TRIANGLE_GEOMETRY_SUPPORTED: return 1;
    case RTC_DEVICE_PROPERTY_QUAD_GEOMETRY_SUPPORTED: return 1;
    case RTC_DEVICE_PROPERTY_SUBDIVISION_GEOMETRY_SUPPORTED: return 1;
    case RTC_DEVICE_PROPERTY_CURVE_GEOMETRY_SUPPORTED: return 0;
    case RTC_DEVICE_PROPERTY_USER_GEOMETRY_SUPPORTED: return 1;
    case RTC_DEVICE_PROPERTY_POINT_GEOMETRY_SUPPORTED: return 0;
    case RTC_DEVICE_PROPERTY_TASKING_SYSTEM: return 1;  // 1 = TBB, as in Debian's build
    case RTC_DEVICE_PROPERTY_JOIN_COMMIT_SUPPORTED: return 1;
    case RTC_DEVICE_PROPERTY_PARALLEL_COMMIT_SUPPORTED: return 1;
  }
  // Embree answers its internal debugging properties (2000000 and up) with pointers into its own
  // code; embree_verify queries them at start-up. obvh has no such internals and answers 0.
  if (prop >= 2000000 && prop < 2000100) return 0;
  fail(RTC_ERROR_INVALID_ARGUMENT, "unknown readable property");
}

// Embree reserves 1000000..1000003 for internal settings that may be set without a device;
// Debian's tutorials set them at start-up. obvh has no such settings and accepts them as no-ops.
bool isInternalProperty(int prop) { return prop >= 1000000 && prop < 1000004; }

}  // namespace

RTC_API RTCDevice rtcNewDevice(const char* config) {
  return guarded(nullptr, RTCDevice(nullptr), [&] {
    const DeviceConfig parsed = parseDeviceConfig(effectiveConfigString(config));
    return (new Device(parsed))->handle();
  });
}

RTC_API void rtcRetainDevice(RTCDevice device) {
  guarded(nullptr, [&] { requireHandle(Device::from(device))->retain(); });
}

RTC_API void rtcReleaseDevice(RTCDevice device) {
  guarded(nullptr, [&] { requireHandle(Device::from(device))->release(); });
}

RTC_API ssize_t rtcGetDeviceProperty(RTCDevice device, RTCDeviceProperty prop) {
  Device* d = Device::from(device);
  return guarded(d, ssize_t(0), [&] {
    requireHandle(d);
    return queryProperty(*d, enumBits(prop));
  });
}

RTC_API void rtcSetDeviceProperty(RTCDevice device, const RTCDeviceProperty prop, ssize_t) {
  Device* d = Device::from(device);
  guarded(d, [&] {
    if (isInternalProperty(enumBits(prop))) return;
    requireHandle(d);
    fail(RTC_ERROR_INVALID_ARGUMENT, "unknown writable property");
  });
}

RTC_API RTCError rtcGetDeviceError(RTCDevice device) { return takeError(Device::from(device)); }

RTC_API void rtcSetDeviceErrorFunction(RTCDevice device, RTCErrorFunction error, void* userPtr) {
  Device* d = Device::from(device);
  guarded(d, [&] { requireHandle(d)->setErrorFunction(error, userPtr); });
}

RTC_API void rtcSetDeviceMemoryMonitorFunction(RTCDevice device, RTCMemoryMonitorFunction memoryMonitor,
                                               void* userPtr) {
  Device* d = Device::from(device);
  guarded(d, [&] { requireHandle(d)->setMemoryMonitor(memoryMonitor, userPtr); });
}
