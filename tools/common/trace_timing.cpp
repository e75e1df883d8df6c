#include "trace_timing.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <type_traits>

namespace obvh::tools {
namespace {

void asRayHits(const std::vector<RTCRay>& rays, std::vector<RTCRayHit>& out) {
  out.resize(rays.size());
  for (size_t i = 0; i < rays.size(); ++i) {
    RTCRayHit rh{};
    rh.ray = rays[i];
    rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
    rh.hit.primID = RTC_INVALID_GEOMETRY_ID;
    rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
    out[i] = rh;
  }
}

// What a timed pass traces, written into memory this thread keeps for its later passes (one buffer
// an item type): a new vector every pass, tens of megabytes, had the kernel fault in and clear its
// pages again each time, which took about half of obvh_bench's wall time (system time, perf: 1.6
// million page faults in one pass of every row on the bunny) outside the timed work.
template <typename Item>
std::vector<Item>& passItems() {
  thread_local std::vector<Item> items;
  return items;
}

// Runs query(context, item) over all items on all cores `runs` times, the items written afresh by
// fill(items) before each run; returns the median Mrays/s (rayCount rays in all).
template <typename Item, typename Fill, typename Query>
double timedRuns(Fill&& fill, int runs, std::vector<Item>* answers, Query query, size_t rayCount,
                 RTCIntersectContextFlags contextFlags) {
  std::vector<double> rates;
  std::vector<Item>& work = passItems<Item>();
  for (int r = 0; r < runs; ++r) {
    fill(work);
    const double ms = millisecondsOf([&] {
      tbb::parallel_for(tbb::blocked_range<size_t>(0, work.size(), 256), [&](const tbb::blocked_range<size_t>& b) {
        RTCIntersectContext context;
        rtcInitIntersectContext(&context);
        context.flags = contextFlags;
        for (size_t i = b.begin(); i < b.end(); ++i) query(&context, &work[i]);
      });
    });
    rates.push_back(double(rayCount) / (ms * 1e3));
    if (r == 0 && answers) *answers = work;
  }
  return median(rates);
}

// Eight rays a packet, in the order given (consecutive pixels of a row are coherent); the last
// packet's unused lanes are invalid.
struct Packet8 {
  alignas(32) int valid[8];
  RTCRayHit8 rayhit;
};

void copyRayToLane(RTCRayN* n, const RTCRay& r, unsigned lane) {
  RTCRayN_org_x(n, 8, lane) = r.org_x, RTCRayN_org_y(n, 8, lane) = r.org_y, RTCRayN_org_z(n, 8, lane) = r.org_z;
  RTCRayN_dir_x(n, 8, lane) = r.dir_x, RTCRayN_dir_y(n, 8, lane) = r.dir_y, RTCRayN_dir_z(n, 8, lane) = r.dir_z;
  RTCRayN_tnear(n, 8, lane) = r.tnear, RTCRayN_tfar(n, 8, lane) = r.tfar, RTCRayN_time(n, 8, lane) = r.time;
  RTCRayN_mask(n, 8, lane) = r.mask, RTCRayN_id(n, 8, lane) = r.id, RTCRayN_flags(n, 8, lane) = r.flags;
}

void packets8(const std::vector<RTCRay>& rays, std::vector<Packet8>& packets) {
  packets.assign((rays.size() + 7) / 8, Packet8{});
  for (size_t i = 0; i < packets.size() * 8; ++i) {
    Packet8& p = packets[i / 8];
    const unsigned lane = unsigned(i % 8);
    p.valid[lane] = i < rays.size() ? -1 : 0;
    RTCRayHit rh{};
    if (i < rays.size()) rh.ray = rays[i];
    rh.hit.geomID = rh.hit.primID = rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
    auto* n = reinterpret_cast<RTCRayHitN*>(&p.rayhit);
    copyRayToLane(RTCRayHitN_RayN(n, 8), rh.ray, lane);
    rtcCopyHitToHitN(RTCRayHitN_HitN(n, 8), &rh.hit, 8, lane);
  }
}

template <typename Out>
void unpack8(const std::vector<Packet8>& packets, size_t count, std::vector<Out>& out) {
  out.resize(count);
  for (size_t i = 0; i < count; ++i) {
    auto* n = reinterpret_cast<RTCRayHitN*>(const_cast<RTCRayHit8*>(&packets[i / 8].rayhit));
    const RTCRayHit rh = rtcGetRayHitFromRayHitN(n, 8, unsigned(i % 8));
    if constexpr (std::is_same_v<Out, RTCRayHit>) out[i] = rh;
    else out[i] = rh.ray;
  }
}

// timedRuns over the rays in packets of eight (packets8); query(context, packet) traces one.
template <typename Out, typename Query>
double packetRuns(const std::vector<RTCRay>& rays, int runs, std::vector<Out>* answers,
                  RTCIntersectContextFlags contextFlags, Query query) {
  std::vector<Packet8> first;
  const double rate =
      timedRuns([&](std::vector<Packet8>& items) { packets8(rays, items); }, runs, answers ? &first : nullptr, query,
                rays.size(), contextFlags);
  if (answers) unpack8(first, rays.size(), *answers);
  return rate;
}

// kStreamRays consecutive rays (fewer in the last stream) for rtcIntersect1M / rtcOccluded1M.
template <typename RayType>
struct Stream {
  RayType rays[kStreamRays];
  unsigned count = 0;
};

template <typename RayType>
void streamsOf(const std::vector<RayType>& rays, std::vector<Stream<RayType>>& streams) {
  streams.assign((rays.size() + kStreamRays - 1) / kStreamRays, Stream<RayType>{});
  for (size_t i = 0; i < rays.size(); ++i) streams[i / kStreamRays].rays[streams[i / kStreamRays].count++] = rays[i];
}

template <typename RayType>
void unpackStreams(const std::vector<Stream<RayType>>& streams, std::vector<RayType>& out) {
  out.clear();
  for (const Stream<RayType>& s : streams) out.insert(out.end(), s.rays, s.rays + s.count);
}

// timedRuns over the rays in streams; traceStream(context, first ray, count) traces one.
template <typename RayType, typename TraceStream>
double streamRuns(const std::vector<RayType>& rays, int runs, std::vector<RayType>* answers,
                  RTCIntersectContextFlags contextFlags, TraceStream traceStream) {
  std::vector<Stream<RayType>> first;
  const double rate = timedRuns(
      [&](std::vector<Stream<RayType>>& items) { streamsOf(rays, items); }, runs, answers ? &first : nullptr,
      [&](RTCIntersectContext* context, Stream<RayType>* s) { traceStream(context, s->rays, s->count); }, rays.size(),
      contextFlags);
  if (answers) unpackStreams(first, *answers);
  return rate;
}

}  // namespace

double median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  const size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

double traceIntersectMrays(const RtcLibrary& lib, RTCScene scene, const std::vector<RTCRay>& rays, int runs,
                           std::vector<RTCRayHit>* answers,
                           RTCIntersectContextFlags contextFlags) {
  return timedRuns(
      [&](std::vector<RTCRayHit>& items) { asRayHits(rays, items); }, runs, answers,
      [&](RTCIntersectContext* context, RTCRayHit* rayhit) { lib.rtcIntersect1(scene, context, rayhit); }, rays.size(),
      contextFlags);
}

double traceOccludedMrays(const RtcLibrary& lib, RTCScene scene, const std::vector<RTCRay>& rays, int runs,
                          std::vector<RTCRay>* answers,
                          RTCIntersectContextFlags contextFlags) {
  return timedRuns(
      [&](std::vector<RTCRay>& items) { items.assign(rays.begin(), rays.end()); }, runs, answers,
      [&](RTCIntersectContext* context, RTCRay* ray) { lib.rtcOccluded1(scene, context, ray); }, rays.size(),
      contextFlags);
}

double traceIntersect8Mrays(const RtcLibrary& lib, RTCScene scene, const std::vector<RTCRay>& rays, int runs,
                            std::vector<RTCRayHit>* answers,
                            RTCIntersectContextFlags contextFlags) {
  return packetRuns(rays, runs, answers, contextFlags, [&](RTCIntersectContext* context, Packet8* p) {
    lib.rtcIntersect8(p->valid, scene, context, &p->rayhit);
  });
}

double traceIntersect8OneSlotMrays(const RtcLibrary& lib, RTCScene scene, const std::vector<RTCRay>& rays, int runs,
                                   std::vector<RTCRayHit>* answers, RTCIntersectContextFlags contextFlags) {
  return packetRuns(rays, runs, answers, contextFlags, [&](RTCIntersectContext* context, Packet8* p) {
    Packet8 slot = *p;  // the thread's one packet, filled for every packet and read back after it
    lib.rtcIntersect8(slot.valid, scene, context, &slot.rayhit);
    *p = slot;
  });
}

double traceOccluded8Mrays(const RtcLibrary& lib, RTCScene scene, const std::vector<RTCRay>& rays, int runs,
                           std::vector<RTCRay>* answers,
                           RTCIntersectContextFlags contextFlags) {
  return packetRuns(rays, runs, answers, contextFlags, [&](RTCIntersectContext* context, Packet8* p) {
    lib.rtcOccluded8(p->valid, scene, context, &p->rayhit.ray);
  });
}

double traceIntersect1MMrays(const RtcLibrary& lib, RTCScene scene, const std::vector<RTCRay>& rays, int runs,
                             std::vector<RTCRayHit>* answers,
                             RTCIntersectContextFlags contextFlags) {
  std::vector<RTCRayHit>& rayHits = passItems<RTCRayHit>();  // free here: the passes trace streams
  asRayHits(rays, rayHits);
  return streamRuns(rayHits, runs, answers, contextFlags,
                    [&](RTCIntersectContext* context, RTCRayHit* first, unsigned count) {
                      lib.rtcIntersect1M(scene, context, first, count, sizeof(RTCRayHit));
                    });
}

double traceOccluded1MMrays(const RtcLibrary& lib, RTCScene scene, const std::vector<RTCRay>& rays, int runs,
                            std::vector<RTCRay>* answers,
                            RTCIntersectContextFlags contextFlags) {
  return streamRuns(rays, runs, answers, contextFlags, [&](RTCIntersectContext* context, RTCRay* first, unsigned count) {
    lib.rtcOccluded1M(scene, context, first, count, sizeof(RTCRay));
  });
}

double traceQueryMrays(const RtcLibrary& lib, RTCScene scene, TracedQuery query, const std::vector<RTCRay>& rays,
                       RTCIntersectContextFlags contextFlags, std::vector<RTCRayHit>* hits,
                       std::vector<RTCRay>* occluded) {
  switch (query) {
    case TracedQuery::Intersect1: return traceIntersectMrays(lib, scene, rays, 1, hits, contextFlags);
    case TracedQuery::Intersect8: return traceIntersect8Mrays(lib, scene, rays, 1, hits, contextFlags);
    case TracedQuery::Intersect8OneSlot: return traceIntersect8OneSlotMrays(lib, scene, rays, 1, hits, contextFlags);
    case TracedQuery::Intersect1M: return traceIntersect1MMrays(lib, scene, rays, 1, hits, contextFlags);
    case TracedQuery::Occluded1: return traceOccludedMrays(lib, scene, rays, 1, occluded, contextFlags);
    case TracedQuery::Occluded8: return traceOccluded8Mrays(lib, scene, rays, 1, occluded, contextFlags);
    case TracedQuery::Occluded1M: return traceOccluded1MMrays(lib, scene, rays, 1, occluded, contextFlags);
  }
  return 0.0;
}

}  // namespace obvh::tools
