// The rays the ladder traces (and `obvh_bench probe`): the main bench's floor rows and three
// incoherent kinds, each with the API that traces it and the intersect context's coherence hint.
// Shadow rays and diffuse bounces start from Embree's hits of the primary rays, so every library
// traces the same rays.
#pragma once

#include <embree3/rtcore.h>

#include <cstddef>
#include <vector>

#include "ray_generation.h"
#include "rtc_library.h"
#include "trace_timing.h"

namespace obvh::tools {

struct Workload {
  const char* name;  // as the ladder's table prints it
  const char* key;   // as `obvh_bench probe --workload` takes it
  TracedQuery query;
  std::vector<RTCRay> rays;
  RTCIntersectContextFlags flags = RTC_INTERSECT_CONTEXT_FLAG_INCOHERENT;
};

// embreeScene: the scene committed with Debian's Embree (embree), whose hits seed the secondary rays.
std::vector<Workload> ladderWorkloads(const RtcLibrary& embree, RTCScene embreeScene, size_t randomRayCount);

}  // namespace obvh::tools
