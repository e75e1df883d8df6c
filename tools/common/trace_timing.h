// Timed tracing through a loaded library: rays split over all cores with TBB, medians over runs.
#pragma once

#include <embree3/rtcore.h>

#include <chrono>
#include <vector>

#include "rtc_library.h"

namespace obvh::tools {

double median(std::vector<double> values);

template <typename F>
double millisecondsOf(F&& f) {
  const auto start = std::chrono::steady_clock::now();
  f();
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

// rtcIntersect1 over every ray, `runs` times; returns the median Mrays/s. When answers is given it
// receives the first run's hit records. Every intersect context gets contextFlags (Embree's
// coherence hint: RTC_INTERSECT_CONTEXT_FLAG_COHERENT for camera rays and shadow rays to one light).
double traceIntersectMrays(const RtcLibrary& lib, RTCScene scene, const std::vector<RTCRay>& rays, int runs,
                           std::vector<RTCRayHit>* answers = nullptr,
                           RTCIntersectContextFlags contextFlags = RTC_INTERSECT_CONTEXT_FLAG_INCOHERENT);

// rtcOccluded1 over every ray; answers get the rays as the first run left them (tfar = -inf: occluded).
double traceOccludedMrays(const RtcLibrary& lib, RTCScene scene, const std::vector<RTCRay>& rays, int runs,
                          std::vector<RTCRay>* answers = nullptr,
                          RTCIntersectContextFlags contextFlags = RTC_INTERSECT_CONTEXT_FLAG_INCOHERENT);

// The same through eight-ray packets (rtcIntersect8 / rtcOccluded8) of consecutive rays.
double traceIntersect8Mrays(const RtcLibrary& lib, RTCScene scene, const std::vector<RTCRay>& rays, int runs,
                            std::vector<RTCRayHit>* answers = nullptr,
                            RTCIntersectContextFlags contextFlags = RTC_INTERSECT_CONTEXT_FLAG_INCOHERENT);
// rtcIntersect8 as an application that fills one packet on its stack for every eight rays does:
// each packet is copied into one slot, traced there and copied back. The packet's memory is then
// in cache before the call, and the memory after it too (obvh prefetches the memory after a
// packet, where an array of packets keeps the next one).
double traceIntersect8OneSlotMrays(const RtcLibrary& lib, RTCScene scene, const std::vector<RTCRay>& rays, int runs,
                                   std::vector<RTCRayHit>* answers = nullptr,
                                   RTCIntersectContextFlags contextFlags = RTC_INTERSECT_CONTEXT_FLAG_INCOHERENT);
double traceOccluded8Mrays(const RtcLibrary& lib, RTCScene scene, const std::vector<RTCRay>& rays, int runs,
                           std::vector<RTCRay>* answers = nullptr,
                           RTCIntersectContextFlags contextFlags = RTC_INTERSECT_CONTEXT_FLAG_INCOHERENT);

// The same through streams (rtcIntersect1M / rtcOccluded1M) of kStreamRays consecutive rays, as an
// application tracing a tile or a row segment of pixels at a time would.
constexpr size_t kStreamRays = 64;
double traceIntersect1MMrays(const RtcLibrary& lib, RTCScene scene, const std::vector<RTCRay>& rays, int runs,
                             std::vector<RTCRayHit>* answers = nullptr,
                             RTCIntersectContextFlags contextFlags = RTC_INTERSECT_CONTEXT_FLAG_INCOHERENT);
double traceOccluded1MMrays(const RtcLibrary& lib, RTCScene scene, const std::vector<RTCRay>& rays, int runs,
                            std::vector<RTCRay>* answers = nullptr,
                            RTCIntersectContextFlags contextFlags = RTC_INTERSECT_CONTEXT_FLAG_INCOHERENT);

// The query APIs the benchmarks time, each through the function above that traces it.
enum class TracedQuery { Intersect1, Intersect8, Intersect8OneSlot, Intersect1M, Occluded1, Occluded8, Occluded1M };
inline bool isOcclusion(TracedQuery q) {
  return q == TracedQuery::Occluded1 || q == TracedQuery::Occluded8 || q == TracedQuery::Occluded1M;
}

// One timed pass of `query` over rays; returns Mrays/s. hits receives an intersect query's records,
// occluded an occlusion query's rays as it left them (either may be null, and the other kind's is
// ignored).
double traceQueryMrays(const RtcLibrary& lib, RTCScene scene, TracedQuery query, const std::vector<RTCRay>& rays,
                       RTCIntersectContextFlags contextFlags, std::vector<RTCRayHit>* hits = nullptr,
                       std::vector<RTCRay>* occluded = nullptr);

}  // namespace obvh::tools
