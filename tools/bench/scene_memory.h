// What a library says a committed scene costs in memory, through the device memory monitor
// (rtcSetDeviceMemoryMonitorFunction), so that Embree and obvh are measured by the same rule: the
// bytes each library reports allocating, whatever allocator it uses.
#pragma once

#include <embree3/rtcore.h>

#include <string>

#include "rtc_library.h"
#include "scene_data.h"

namespace obvh::tools {

struct SceneMemory {
  double heldMegabytes = 0;  // reported and not yet released once the scene is committed
};

// Builds and commits scene on a fresh device (rtcNewDevice(config)) of lib; the figure includes the
// geometry buffers (the scene's buffers are the library's own, rtcSetNewGeometryBuffer).
SceneMemory measureSceneMemory(const RtcLibrary& lib, const std::string& config, const SceneData& scene,
                               RTCBuildQuality quality);

}  // namespace obvh::tools
