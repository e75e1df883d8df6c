#include "trace_timing.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>

namespace obvh::tools {
namespace {

std::vector<RTCRayHit> asRayHits(const std::vector<RTCRay>& rays) {
  std::vector<RTCRayHit> out(rays.size());
  for (size_t i = 0; i < rays.size(); ++i) {
    out[i].ray = rays[i];
    out[i].hit.geomID = RTC_INVALID_GEOMETRY_ID;
    out[i].hit.primID = RTC_INVALID_GEOMETRY_ID;
    out[i].hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
  }
  return out;
}

// Runs query(context, item) over all items on all cores `runs` times; returns the median Mrays/s.
template <typename Item, typename Query>
double timedRuns(std::vector<Item> items, int runs, std::vector<Item>* answers, Query query) {
  std::vector<double> rates;
  for (int r = 0; r < runs; ++r) {
    std::vector<Item> work = items;
    const double ms = millisecondsOf([&] {
      tbb::parallel_for(tbb::blocked_range<size_t>(0, work.size(), 256), [&](const tbb::blocked_range<size_t>& b) {
        RTCIntersectContext context;
        rtcInitIntersectContext(&context);
        for (size_t i = b.begin(); i < b.end(); ++i) query(&context, &work[i]);
      });
    });
    rates.push_back(double(work.size()) / (ms * 1e3));
    if (r == 0 && answers) *answers = std::move(work);
  }
  return median(rates);
}

}  // namespace

double median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  const size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

double traceIntersectMrays(const RtcLibrary& lib, RTCScene scene, const std::vector<RTCRay>& rays, int runs,
                           std::vector<RTCRayHit>* answers) {
  return timedRuns(asRayHits(rays), runs, answers,
                   [&](RTCIntersectContext* context, RTCRayHit* rayhit) { lib.rtcIntersect1(scene, context, rayhit); });
}

double traceOccludedMrays(const RtcLibrary& lib, RTCScene scene, const std::vector<RTCRay>& rays, int runs,
                          std::vector<RTCRay>* answers) {
  return timedRuns(rays, runs, answers,
                   [&](RTCIntersectContext* context, RTCRay* ray) { lib.rtcOccluded1(scene, context, ray); });
}

}  // namespace obvh::tools
