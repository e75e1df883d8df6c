#include "device.h"

#include <cstdio>

#include "api_error.h"

namespace obvh::api {
namespace {
thread_local RTCError deviceLessError = RTC_ERROR_NONE;
}

Device::Device(const DeviceConfig& config) : config_(config) {
  arena_ = config.threads > 0 ? std::make_unique<tbb::task_arena>(config.threads)
                              : std::make_unique<tbb::task_arena>();
}

void Device::setErrorFunction(RTCErrorFunction fn, void* userPtr) {
  std::lock_guard<std::mutex> lock(mutex_);
  errorFunction_ = fn;
  errorUserPtr_ = userPtr;
}

void Device::setMemoryMonitor(RTCMemoryMonitorFunction fn, void* userPtr) {
  std::lock_guard<std::mutex> lock(mutex_);
  memoryMonitor_ = fn;
  memoryUserPtr_ = userPtr;
}

void Device::reportMemory(ssize_t bytes, bool post) {
  RTCMemoryMonitorFunction fn;
  void* userPtr;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    fn = memoryMonitor_;
    userPtr = memoryUserPtr_;
  }
  if (fn && bytes != 0 && !fn(userPtr, bytes, post) && bytes > 0)
    fail(RTC_ERROR_OUT_OF_MEMORY, "memory monitor refused the allocation");
}

void Device::recordError(RTCError code, const char* message) {
  // verbose=1 (e.g. through OBVH_CONFIG) makes errors visible in programs that do not print them.
  if (config_.verbose >= 1) std::fprintf(stderr, "obvh: error %d: %s\n", int(code), message);
  RTCErrorFunction fn;
  void* userPtr;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    RTCError& stored = errors_[std::this_thread::get_id()];
    if (stored == RTC_ERROR_NONE) stored = code;
    fn = errorFunction_;
    userPtr = errorUserPtr_;
  }
  if (fn) fn(userPtr, code, message);
}

RTCError Device::takeError() {
  std::lock_guard<std::mutex> lock(mutex_);
  auto it = errors_.find(std::this_thread::get_id());
  if (it == errors_.end()) return RTC_ERROR_NONE;
  const RTCError code = it->second;
  errors_.erase(it);
  return code;
}

void reportError(Device* device, RTCError code, const char* message) {
  if (device) {
    device->recordError(code, message);
  } else if (deviceLessError == RTC_ERROR_NONE) {
    deviceLessError = code;
  }
}

RTCError takeError(Device* device) {
  if (device) return device->takeError();
  const RTCError code = deviceLessError;
  deviceLessError = RTC_ERROR_NONE;
  return code;
}

}  // namespace obvh::api
