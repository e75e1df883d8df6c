// Embree-style error reporting: every entry point converts failures into an RTCError that is
// stored per device and thread (first error wins until read) and passed to the error callback.
#pragma once

#include <embree3/rtcore.h>

#include <new>
#include <stdexcept>
#include <string>

namespace obvh::api {

class Device;

class ApiError : public std::runtime_error {
 public:
  ApiError(RTCError code, const std::string& message) : std::runtime_error(message), code_(code) {}
  RTCError code() const { return code_; }

 private:
  RTCError code_;
};

[[noreturn]] inline void fail(RTCError code, const std::string& message) { throw ApiError(code, message); }

// Records an error for device (nullptr: the calling thread's device-less error) and calls the callback.
void reportError(Device* device, RTCError code, const char* message);

// Returns and clears the stored error.
RTCError takeError(Device* device);

// Runs body; any exception becomes an RTCError on device and the call returns fallback. Not
// noexcept on purpose: an error callback may throw (embree_verify's does), and as with Embree that
// exception then propagates to the caller of the API function.
template <typename Result, typename Body>
Result guarded(Device* device, Result fallback, Body&& body) {
  try {
    return body();
  } catch (const ApiError& e) {
    reportError(device, e.code(), e.what());
  } catch (const std::bad_alloc&) {
    reportError(device, RTC_ERROR_OUT_OF_MEMORY, "out of memory");
  } catch (const std::exception& e) {
    reportError(device, RTC_ERROR_UNKNOWN, e.what());
  } catch (...) {
    reportError(device, RTC_ERROR_UNKNOWN, "unknown exception");
  }
  return fallback;
}

template <typename Body>
void guarded(Device* device, Body&& body) {
  guarded(device, 0, [&] {
    body();
    return 0;
  });
}

template <typename T>
T* requireHandle(T* handle) {
  if (handle == nullptr) fail(RTC_ERROR_INVALID_ARGUMENT, "invalid argument: null handle");
  return handle;
}

}  // namespace obvh::api
