// RTCDevice: configuration, error state, callbacks and the task arena builds run in.
#pragma once

#include <embree3/rtcore.h>

#include <tbb/task_arena.h>

#include <memory>
#include <mutex>
#include <thread>
#include <unordered_map>

#include "device_config.h"
#include "ref_counted.h"

namespace obvh::api {

class Device : public RefCounted {
 public:
  explicit Device(const DeviceConfig& config);

  const DeviceConfig& config() const { return config_; }

  void setErrorFunction(RTCErrorFunction fn, void* userPtr);
  void setMemoryMonitor(RTCMemoryMonitorFunction fn, void* userPtr);
  // Tells the memory monitor about a change of bytes; throws OUT_OF_MEMORY when it refuses.
  void reportMemory(ssize_t bytes, bool post);

  void recordError(RTCError code, const char* message);
  RTCError takeError();

  // Runs work inside the device's arena so that "threads=N" bounds the builders' parallelism.
  template <typename F>
  void execute(F&& work) {
    arena_->execute(std::forward<F>(work));
  }

  static Device* from(RTCDevice handle) { return reinterpret_cast<Device*>(handle); }
  RTCDevice handle() { return reinterpret_cast<RTCDevice>(this); }

 private:
  DeviceConfig config_;
  std::unique_ptr<tbb::task_arena> arena_;

  std::mutex mutex_;
  std::unordered_map<std::thread::id, RTCError> errors_;
  RTCErrorFunction errorFunction_ = nullptr;
  void* errorUserPtr_ = nullptr;
  RTCMemoryMonitorFunction memoryMonitor_ = nullptr;
  void* memoryUserPtr_ = nullptr;
};

}  // namespace obvh::api
