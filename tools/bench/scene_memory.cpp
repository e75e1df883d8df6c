#include "scene_memory.h"

#include <atomic>
#include <stdexcept>

namespace obvh::tools {
namespace {

// Called by the library, possibly from its build threads: every report (pre or post) counts once.
bool recordAllocation(void* user, ssize_t bytes, bool /*post*/) {
  static_cast<std::atomic<long long>*>(user)->fetch_add(bytes);
  return true;
}

}  // namespace

SceneMemory measureSceneMemory(const RtcLibrary& lib, const std::string& config, const SceneData& scene,
                               RTCBuildQuality quality) {
  RTCDevice device = lib.rtcNewDevice(config.c_str());
  if (!device) throw std::runtime_error(lib.label + ": rtcNewDevice failed");
  std::atomic<long long> held{0};
  // Installed after the device exists, so that only the scene's own allocations are counted.
  lib.rtcSetDeviceMemoryMonitorFunction(device, recordAllocation, &held);
  SceneMemory memory;
  bool failed = false;
  {
    CommittedScene committed(lib, device, scene, RTC_SCENE_FLAG_NONE, quality);
    failed = lib.rtcGetDeviceError(device) != RTC_ERROR_NONE;
    memory.heldMegabytes = double(held.load()) / (1024.0 * 1024.0);
  }
  lib.rtcSetDeviceMemoryMonitorFunction(device, nullptr, nullptr);
  lib.rtcReleaseDevice(device);
  if (failed) throw std::runtime_error(lib.label + ": committing the scene failed");
  return memory;
}

}  // namespace obvh::tools
