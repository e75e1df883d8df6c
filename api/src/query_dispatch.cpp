#include "query_dispatch.h"
#include "memory/prefetch.h"
#include "memory/uninitialized_array.h"
#include "traversal_statistics_state.h"

#include <algorithm>
#include <cstddef>
#include <limits>
#include <type_traits>

#ifdef __SSE2__
#include <emmintrin.h>

#include "simd/cpu_features.h"
#include "simd/float4_sse.h"
#include "simd/float8_avx.h"
#include "traversal/packet_gate.h"
#endif

namespace obvh::api {
namespace {

// Embree pushes the current instance ID into the context while it traverses an instance, so
// callbacks can read it; this does the same for the duration of one callback.
class InstanceIdScope {
 public:
  InstanceIdScope(RTCIntersectContext& context, uint32_t instID) : context_(context), saved_(context.instID[0]) {
    context_.instID[0] = instID;
  }
  ~InstanceIdScope() { context_.instID[0] = saved_; }

 private:
  RTCIntersectContext& context_;
  unsigned saved_;
};

Hit backendHit(const RTCHit& hit) {
  Hit out;
  out.Ng = {hit.Ng_x, hit.Ng_y, hit.Ng_z};
  out.u = hit.u, out.v = hit.v;
  out.primID = hit.primID;
  out.geomID = hit.geomID;
  out.instID = hit.instID[0];
  return out;
}

}  // namespace

QueryDispatch::QueryDispatch(const Scene& scene, RTCIntersectContext& context)
    : scene_(scene), context_(context), masksOn_(scene.device()->config().rayMasks) {
  state_.contextFilter = (scene.flags() & RTC_SCENE_FLAG_CONTEXT_FILTER_FUNCTION) && context.filter;
  // Most scenes have no filters and no user geometry; their queries never leave the backend.
  if (scene.needsCallbacks() || state_.contextFilter) state_.callbacks = this;
  state_.instID = context.instID[0];
  state_.counters = threadTraversalCounters();
  state_.coherent = declaresCoherentRays(context);
}

RTCRay QueryDispatch::embreeRay(const Ray& ray, float tfar) const {
  RTCRay r = *original_;
  r.org_x = ray.org.x, r.org_y = ray.org.y, r.org_z = ray.org.z;
  r.dir_x = ray.dir.x, r.dir_y = ray.dir.y, r.dir_z = ray.dir.z;
  r.tnear = ray.tnear;
  r.tfar = tfar;
  return r;
}

bool QueryDispatch::intersect(RTCRayHit& rayhit) {
  original_ = &rayhit.ray;
  Ray ray = backendRay(rayhit.ray, masksOn_);
  Hit hit;
  if (!scene_.accel().intersect(ray, hit, state_)) return false;
  rayhit.ray.tfar = ray.tfar;
  rayhit.hit = embreeHit(hit);
  return true;
}

bool QueryDispatch::occluded(RTCRay& ray) {
  original_ = &ray;
  if (!scene_.accel().occluded(backendRay(ray, masksOn_), state_)) return false;
  ray.tfar = -std::numeric_limits<float>::infinity();
  return true;
}

namespace {

// Lanes whose valid entry is -1 are active, as in Embree; a null mask activates every lane.
bool laneActive(const int* valid, unsigned lane) { return valid == nullptr || valid[lane] == -1; }

Ray laneRay(RTCRayN* rays, unsigned N, unsigned i, bool masksOn) {
  Ray ray;
  ray.org = {RTCRayN_org_x(rays, N, i), RTCRayN_org_y(rays, N, i), RTCRayN_org_z(rays, N, i)};
  ray.dir = {RTCRayN_dir_x(rays, N, i), RTCRayN_dir_y(rays, N, i), RTCRayN_dir_z(rays, N, i)};
  ray.tnear = RTCRayN_tnear(rays, N, i);
  ray.tfar = RTCRayN_tfar(rays, N, i);
  ray.mask = masksOn ? RTCRayN_mask(rays, N, i) : 0xFFFFFFFFu;
  ray.time = RTCRayN_time(rays, N, i);
  return ray;
}

#ifdef __SSE2__
// gatherLiveLanes for lanes in fours (rtcIntersect4/8/16, rtcOccluded4/8/16): the rows of four lanes
// (org_x, org_y, org_z, tnear) and (dir_x, dir_y, dir_z, time) transposed are the first 32 bytes
// of four Rays, (tfar, mask) interleaved the last 8. Every lane of four with a live one is written
// (the rays array is scratch; only the live lanes are read). Lane by lane, the conversion was a
// tenth of a coherent rtcIntersect8 packet's time (perf, bunny primary rays). Four lanes none of
// which is live read no more rows than validity and the segment: converted anyway, the bench's
// shadow packets (most of them empty) traced 8% slower than lane by lane.
template <typename Width>
uint32_t gatherLiveLanesByFours(const int* valid, RTCRayN* rayN, Width width, unsigned first, unsigned count,
                                bool masksOn, const PacketGate* gate, Ray* rays) {
  const unsigned N = width;
  static_assert(sizeof(Ray) == 40 && offsetof(Ray, dir) == 16 && offsetof(Ray, tfar) == 32 && offsetof(Ray, mask) == 36);
  const float* row = reinterpret_cast<const float*>(rayN);  // RTCRayN: twelve rows of N lanes
  uint32_t live = 0;
  for (unsigned k = 0; k < count; k += 4) {
    const unsigned i = first + k;
    const auto lanes = [&](int r) { return _mm_loadu_ps(row + unsigned(r) * N + i); };
    const int active = valid == nullptr ? 15
                                        : _mm_movemask_ps(_mm_castsi128_ps(_mm_cmpeq_epi32(
                                              _mm_loadu_si128(reinterpret_cast<const __m128i*>(valid + i)),
                                              _mm_set1_epi32(-1))));
    const __m128 tfar = lanes(8);
    const int empty = _mm_movemask_ps(_mm_cmpgt_ps(lanes(3), tfar));  // tnear > tfar
    if ((active & ~empty) == 0) continue;  // as shadow packets behind pixels without a hit: no rows read
    int liveHere = active & ~empty;
    if (gate != nullptr && gate->bounded) {  // rays outside the structure's box are not live
      using F = simd::Float4Sse;
      const F org[3] = {F{lanes(0)}, F{lanes(1)}, F{lanes(2)}}, dir[3] = {F{lanes(4)}, F{lanes(5)}, F{lanes(6)}};
      liveHere &= ~lanesMissingGate(*gate, org, dir, F{lanes(3)}, F{tfar}, liveHere);
      if (liveHere == 0) continue;
    }
    live |= uint32_t(liveHere) << k;
    float* out = reinterpret_cast<float*>(rays + k);
    for (int half = 0; half < 2; ++half) {  // org and tnear, then dir and time
      simd::Float4Sse leading[4];             // of the four rays, one each
      simd::Float4Sse::loadColumns(row + unsigned(4 * half) * N + i, N, leading);
      for (int lane = 0; lane < 4; ++lane) leading[lane].storeUnaligned(out + 10 * lane + 4 * half);
    }
    const __m128 mask = masksOn ? lanes(9) : _mm_castsi128_ps(_mm_set1_epi32(-1));
    const __m128 low = _mm_unpacklo_ps(tfar, mask), high = _mm_unpackhi_ps(tfar, mask);
    _mm_storel_pi(reinterpret_cast<__m64*>(out + 8), low);
    _mm_storeh_pi(reinterpret_cast<__m64*>(out + 18), low);
    _mm_storel_pi(reinterpret_cast<__m64*>(out + 28), high);
    _mm_storeh_pi(reinterpret_cast<__m64*>(out + 38), high);
  }
  return live;
}

// gatherLiveLanesByFours for lanes in eights (rtcIntersect8/16, rtcOccluded8/16 on CPUs with AVX2):
// the eight leading rows transposed are the first 32 bytes of eight Rays, one store each. A
// coherent rtcIntersect8 packet on the bunny took 200 instructions to convert in fours, 122 so
// (callgrind). Packets of four keep the four-lane version, which the tests thus still exercise.
template <typename Width>
__attribute__((target("avx2"))) uint32_t gatherLiveLanesByEights(const int* valid, RTCRayN* rayN, Width width,
                                                                 unsigned first, unsigned count, bool masksOn,
                                                                 const PacketGate* gate, Ray* rays) {
  const unsigned N = width;
  static_assert(sizeof(Ray) == 40 && offsetof(Ray, dir) == 16 && offsetof(Ray, tfar) == 32 && offsetof(Ray, mask) == 36);
  const float* row = reinterpret_cast<const float*>(rayN);  // RTCRayN: twelve rows of N lanes
  uint32_t live = 0;
  for (unsigned k = 0; k < count; k += 8) {
    const unsigned i = first + k;
    const float* lanes = row + i;  // row r of these lanes at lanes + r * N
    const int active = valid == nullptr ? 255
                                        : _mm256_movemask_ps(_mm256_castsi256_ps(_mm256_cmpeq_epi32(
                                              _mm256_loadu_si256(reinterpret_cast<const __m256i*>(valid + i)),
                                              _mm256_set1_epi32(-1))));
    const __m256 tfar = _mm256_loadu_ps(lanes + 8 * N);
    const int empty = _mm256_movemask_ps(_mm256_cmp_ps(_mm256_loadu_ps(lanes + 3 * N), tfar, _CMP_GT_OQ));  // tnear > tfar
    if ((active & ~empty) == 0) continue;  // as gatherLiveLanesByFours: no rows read
    int liveHere = active & ~empty;
    if (gate != nullptr && gate->bounded) {  // as gatherLiveLanesByFours
      using F = simd::Float8Avx;
      const F org[3] = {F{_mm256_loadu_ps(lanes)}, F{_mm256_loadu_ps(lanes + N)}, F{_mm256_loadu_ps(lanes + 2 * N)}};
      const F dir[3] = {F{_mm256_loadu_ps(lanes + 4 * N)}, F{_mm256_loadu_ps(lanes + 5 * N)},
                        F{_mm256_loadu_ps(lanes + 6 * N)}};
      liveHere &= ~lanesMissingGate(*gate, org, dir, F{_mm256_loadu_ps(lanes + 3 * N)}, F{tfar}, liveHere);
      if (liveHere == 0) continue;
    }
    live |= uint32_t(liveHere) << k;
    float* out = reinterpret_cast<float*>(rays + k);
    simd::Float8Avx leading[8];  // org, tnear, dir and time of the eight rays, one each
    simd::Float8Avx::loadColumns(lanes, N, leading);
    for (int lane = 0; lane < 8; ++lane) _mm256_storeu_ps(out + 10 * lane, leading[lane].v);
    const __m256 mask = masksOn ? _mm256_loadu_ps(lanes + 9 * N) : _mm256_castsi256_ps(_mm256_set1_epi32(-1));
    // (tfar, mask) pairs of lanes 0, 1, 4, 5 and of lanes 2, 3, 6, 7.
    const __m256 low = _mm256_unpacklo_ps(tfar, mask), high = _mm256_unpackhi_ps(tfar, mask);
    const __m128 pairs[4] = {_mm256_castps256_ps128(low), _mm256_castps256_ps128(high), _mm256_extractf128_ps(low, 1),
                             _mm256_extractf128_ps(high, 1)};
    for (int q = 0; q < 4; ++q) {
      _mm_storel_pi(reinterpret_cast<__m64*>(out + 20 * q + 8), pairs[q]);
      _mm_storeh_pi(reinterpret_cast<__m64*>(out + 20 * q + 18), pairs[q]);
    }
  }
  return live;
}
#endif

// Converts the live lanes of [first, first + count) into rays[0..count) and returns their mask: a
// lane is live when it is active and its segment is not empty (tnear > tfar). Empty segments, as a
// shadow packet's lanes behind pixels without a hit are, can never report anything, and the backend
// would drop them anyway (PacketFrames); not converting them took a packet of eight such lanes
// from 34 to 10 ns (Embree: 12 ns).
uint32_t gatherLiveLanesOneByOne(const int* valid, RTCRayN* rayN, unsigned N, unsigned first, unsigned count,
                                 bool masksOn, Ray* rays) {
  uint32_t live = 0;
  for (unsigned k = 0; k < count; ++k)
    if (laneActive(valid, first + k) && !(RTCRayN_tnear(rayN, N, first + k) > RTCRayN_tfar(rayN, N, first + k)))
      live |= 1u << k;
  for (uint32_t m = live; m; m &= m - 1) {
    const unsigned k = unsigned(__builtin_ctz(m));
    rays[k] = laneRay(rayN, N, first + k, masksOn);
  }
  return live;
}

#ifdef __SSE2__
// Whether [first, first + count) goes in groups of eight lanes: both the gather and the write-back
// take this one decision, since the write-back in eights reads the tfar of every ray of a group,
// which only the gather in eights writes.
inline bool lanesGoInEights(unsigned count) { return count % 8 == 0 && cpuGathersInEights(); }
#endif

// gate: the structure's box (QueryEntry::packetGate), whose missing lanes are not live, or null.
// Width: unsigned, or a std::integral_constant of it (withPacketWidth), with which the gather and
// the write-back address the rows at constant offsets: bunny coherent rtcIntersect8, the gather
// 266 -> 225 instructions a packet and the write-back 58 -> 42 (averaged over all packets,
// callgrind), 1.01-1.03x as fast.
template <typename Width>
inline uint32_t gatherLiveLanes(const int* valid, RTCRayN* rayN, Width width, unsigned first, unsigned count,
                                bool masksOn, const PacketGate* gate, Ray* rays) {
  const unsigned N = width;
#ifdef __SSE2__
  if (lanesGoInEights(count)) return gatherLiveLanesByEights(valid, rayN, width, first, count, masksOn, gate, rays);
  if (count % 4 == 0) return gatherLiveLanesByFours(valid, rayN, width, first, count, masksOn, gate, rays);
#else
  (void)gate;
#endif
  return gatherLiveLanesOneByOne(valid, rayN, N, first, count, masksOn, rays);
}

// The tfar and hit of each lane of [first, first + count) found hitting, from rays[0..count) and
// hits[0..count) (bit k of found: lane first + k).
void writeFoundLanesOneByOne(uint32_t found, const Ray* rays, const Hit* hits, RTCRayN* rayN, RTCHitN* hitN,
                             unsigned N, unsigned first) {
  for (; found; found &= found - 1) {
    const unsigned k = unsigned(__builtin_ctz(found)), i = first + k;
    RTCRayN_tfar(rayN, N, i) = rays[k].tfar;
    const RTCHit hit = embreeHit(hits[k]);
    rtcCopyHitToHitN(hitN, &hit, N, i);
  }
}

#ifdef __SSE2__
// writeFoundLanesOneByOne for lanes in eights on CPUs with AVX2 (the lanes gathered in eights): a
// Hit's eight fields transposed over eight lanes are RTCHitN's eight rows, blended into them under
// the found lanes' mask; the other lanes keep their values (their hits, never written, are loaded
// but not stored). Coherent rtcIntersect8 packets on the bunny took 30 instructions fewer each than
// lane by lane (callgrind).
template <typename Width>
__attribute__((target("avx2"))) void writeFoundLanesByEights(uint32_t found, const Ray* rays, const Hit* hits,
                                                             RTCRayN* rayN, RTCHitN* hitN, Width width, unsigned first,
                                                             unsigned count) {
  const unsigned N = width;
  static_assert(sizeof(Hit) == 8 * sizeof(float) && offsetof(Hit, u) == 12 && offsetof(Hit, v) == 16 &&
                offsetof(Hit, primID) == 20 && offsetof(Hit, geomID) == 24 && offsetof(Hit, instID) == 28 &&
                RTC_MAX_INSTANCE_LEVEL_COUNT == 1);
  // RTCHitN's rows: Ng x, y, z, u, v, primID, geomID, instID; RTCRayN's tfar is its row 8.
  float* hitRows = reinterpret_cast<float*>(hitN);
  float* tfarRow = reinterpret_cast<float*>(rayN) + 8 * N;
  const __m256i laneBits = _mm256_setr_epi32(1, 2, 4, 8, 16, 32, 64, 128);
  for (unsigned k = 0; k < count; k += 8) {
    const int lanes = int((found >> k) & 255);
    if (lanes == 0) continue;
    const __m256 store =
        _mm256_castsi256_ps(_mm256_cmpeq_epi32(_mm256_and_si256(_mm256_set1_epi32(lanes), laneBits), laneBits));
    // Each row is read, blended and written whole: against the lane-by-lane write-back, packets
    // traced 0.985x as fast with masked stores (vmaskmovps) and 1.01x so on this AMD Zen 4 (paired
    // probe, bunny and motorBike, medians of three).
    const auto storeLanes = [store](float* row, __m256 values) __attribute__((target("avx2"))) {
      _mm256_storeu_ps(row, _mm256_blendv_ps(_mm256_loadu_ps(row), values, store));
    };
    simd::Float8Avx fields[8];  // of the eight lanes' hits, one each
    simd::Float8Avx::loadColumns(reinterpret_cast<const float*>(hits + k), 8, fields);
    for (int f = 0; f < 8; ++f) storeLanes(hitRows + f * N + first + k, fields[f].v);
    const __m256 tfar = _mm256_setr_ps(rays[k].tfar, rays[k + 1].tfar, rays[k + 2].tfar, rays[k + 3].tfar,
                                       rays[k + 4].tfar, rays[k + 5].tfar, rays[k + 6].tfar, rays[k + 7].tfar);
    storeLanes(tfarRow + first + k, tfar);
  }
}
#endif

template <typename Width>
inline void writeFoundLanes(uint32_t found, const Ray* rays, const Hit* hits, RTCRayN* rayN, RTCHitN* hitN,
                            Width width, unsigned first, unsigned count) {
  const unsigned N = width;
#ifdef __SSE2__
  if (lanesGoInEights(count)) return writeFoundLanesByEights(found, rays, hits, rayN, hitN, width, first, count);
#endif
  writeFoundLanesOneByOne(found, rays, hits, rayN, hitN, N, first);
}

// Calls body with the packet width N as a constant for Embree's packet sizes 4, 8 and 16: the
// lane-group loops below then fold to their one group (with N a variable, their bookkeeping took
// about 100 instructions a coherent rtcIntersect8 packet on the bunny, callgrind).
template <typename Body>
void withPacketWidth(unsigned N, Body&& body) {
  switch (N) {
    case 4: return body(std::integral_constant<unsigned, 4>{});
    case 8: return body(std::integral_constant<unsigned, 8>{});
    case 16: return body(std::integral_constant<unsigned, 16>{});
    default: return body(N);
  }
}

// An application that traces an array of packets keeps the next one right after this one: its
// lines, prefetched while this packet traces, are in cache when the next call gathers it (the
// hardware's own prefetching left most of them to be fetched then). Paired probe, one thread,
// bunny / motorBike / dragon: the bench's coherent rtcIntersect8 packets 1.09 / 1.11 / 1.07x as
// fast, orthographic ones 1.07 / 1.07 / 1.04x, shadow packets 1.06x; packets traced from one
// stack slot, where the prefetched lines are cached already, 0.99 / 0.97 / 1.00x (the motorBike's
// packets that miss its box are short calls, which the prefetches lengthen). Whole packets: their
// ray rows alone gained 1-3% less. The memory after the packet is only prefetched, never read.
// Rows of N lanes: RTCRayN's twelve (org, tnear, dir, time, tfar, mask, id, flags), then in an
// RTCRayHitN those of RTCHitN (Ng, u, v, primID, geomID, instID per level).
constexpr unsigned kRayRows = 12;
constexpr unsigned kRayHitRows = kRayRows + 7 + RTC_MAX_INSTANCE_LEVEL_COUNT;

// kRows rows of the packet's width (Width as for intersectInLaneGroups below): for Embree's
// packet sizes the size is a constant and the probes unroll.
template <unsigned kRows, typename Width>
[[gnu::always_inline]] inline void prefetchFollowingPacket(const void* packet, Width width) {
  const size_t bytes = size_t(kRows) * unsigned(width) * sizeof(float);
  const char* following = static_cast<const char*>(packet) + bytes;
  if constexpr (std::is_integral_v<Width>)
    prefetchBytes(following, bytes);
  else
    prefetchBytes<size_t(kRows) * Width::value * sizeof(float)>(following);
}

// A packet of N lanes in groups of up to kMaxPacketSize live lanes: trace(rays, hits, live) traces
// one group and returns the lanes that hit, whose hits are written back. Width: unsigned or a
// std::integral_constant of it (withPacketWidth).
template <typename Width, typename Trace>
void intersectInLaneGroups(const int* valid, RTCRayHitN* packet, Width width, bool masksOn, const PacketGate* gate,
                           Trace&& trace) {
  const unsigned N = width;
  RTCRayN* rayN = RTCRayHitN_RayN(packet, N);
  RTCHitN* hitN = RTCRayHitN_HitN(packet, N);
  prefetchFollowingPacket<kRayHitRows>(packet, width);
  for (unsigned first = 0; first < N; first += unsigned(kMaxPacketSize)) {
    const unsigned count = std::min(N - first, unsigned(kMaxPacketSize));
    UninitializedArray<Ray, kMaxPacketSize> rays;  // written in groups of lanes holding a live one
    UninitializedArray<Hit, kMaxPacketSize> hits;
    const uint32_t live = gatherLiveLanes(valid, rayN, width, first, count, masksOn, gate, rays.data());
    if (live == 0) continue;
    const uint32_t found = trace(rays.data(), hits.data(), live);
    if (found) writeFoundLanes(found, rays.data(), hits.data(), rayN, hitN, width, first, count);
  }
}

// The same for occlusion: trace(rays, live) returns the lanes that are blocked. No gate: occlusion
// rays mostly start on surfaces, inside the structure's box (the bench's shadow packets traced 3-4%
// slower through one).
template <typename Width, typename Trace>
void occludedInLaneGroups(const int* valid, RTCRayN* rayN, Width width, bool masksOn, Trace&& trace) {
  const unsigned N = width;
  prefetchFollowingPacket<kRayRows>(rayN, width);
  for (unsigned first = 0; first < N; first += unsigned(kMaxPacketSize)) {
    const unsigned count = std::min(N - first, unsigned(kMaxPacketSize));
    UninitializedArray<Ray, kMaxPacketSize> rays;
    const uint32_t live = gatherLiveLanes(valid, rayN, width, first, count, masksOn, nullptr, rays.data());
    if (live == 0) continue;
    for (uint32_t blocked = trace(rays.data(), live); blocked; blocked &= blocked - 1)
      RTCRayN_tfar(rayN, N, first + unsigned(__builtin_ctz(blocked))) = -std::numeric_limits<float>::infinity();
  }
}

#ifdef __SSE2__
// gatherStreamLanesByEights on a CPU with AVX2: an application ray's first eight floats (org,
// tnear, dir, time) are a backend ray's.
__attribute__((target("avx2"))) uint32_t gatherStreamLanesInAvx2(const RTCRay* const application[8], bool masksOn,
                                                                 const PacketGate& gate, Ray* rays) {
  static_assert(offsetof(RTCRay, org_x) == 0 && offsetof(RTCRay, tnear) == 12 && offsetof(RTCRay, dir_x) == 16 &&
                offsetof(RTCRay, time) == 28);
  using F = simd::Float8Avx;
  const float* leadingRows[8];
  for (int k = 0; k < 8; ++k) leadingRows[k] = &application[k]->org_x;
  F leading[8];  // org x, y, z, tnear, dir x, y, z, time of the eight rays
  F::loadColumnsOf(leadingRows, leading);
  const F tfar = F::fromLanes([&](int k) { return application[k]->tfar; });
  const int empty = _mm256_movemask_ps(_mm256_cmp_ps(leading[3].v, tfar.v, _CMP_GT_OQ));  // tnear > tfar
  int live = ~empty & 255;
  if (live == 0) return 0;
  live &= ~lanesMissingGate(gate, leading, leading + 4, leading[3], tfar, live);
  for (uint32_t m = uint32_t(live); m; m &= m - 1) {
    const int k = __builtin_ctz(m);
    rays[k] = backendRay(*application[k], masksOn);
  }
  return uint32_t(live);
}
#endif

}  // namespace

bool cpuGathersInEights() {
#ifdef __SSE2__
  static const bool cpuHasAvx2 = simd::cpuHasAvx2();
  return cpuHasAvx2;
#else
  return false;
#endif
}

uint32_t gatherStreamLanesByEights(const RTCRay* const application[8], bool masksOn, const PacketGate& gate,
                                   Ray* rays) {
#ifdef __SSE2__
  return gatherStreamLanesInAvx2(application, masksOn, gate, rays);
#else
  (void)application, (void)masksOn, (void)gate, (void)rays;
  return 0;
#endif
}

void intersectPacketDirectly(const QueryEntry& entry, const Scene& scene, const RTCIntersectContext& context,
                             const int* valid, RTCRayHitN* packet, unsigned N) {
  UninitializedArray<QueryState, 1> own;
  const QueryState& state = directQueryState(context, own);
  withPacketWidth(N, [&](auto width) {
    intersectInLaneGroups(valid, packet, width, scene.rayMasks(), &entry.packetGate,
                          [&](Ray* rays, Hit* hits, uint32_t live) {
      return entry.closestPacket(entry.target, rays, hits, live, state);
    });
  });
}

void occludedPacketDirectly(const QueryEntry& entry, const Scene& scene, const RTCIntersectContext& context,
                            const int* valid, RTCRayN* packet, unsigned N) {
  UninitializedArray<QueryState, 1> own;
  const QueryState& state = directQueryState(context, own);
  withPacketWidth(N, [&](auto width) {
    occludedInLaneGroups(valid, packet, width, scene.rayMasks(),
                         [&](const Ray* rays, uint32_t live) { return entry.anyPacket(entry.target, rays, live, state); });
  });
}

// Filters and user geometry receive the application's ray (id, flags, time) one lane at a time,
// so scenes with callbacks keep the lane-by-lane path; packets of more lanes than the backend's
// maximum are traced in chunks.
void QueryDispatch::intersectPacket(const int* valid, RTCRayHitN* packet, unsigned N) {
  RTCRayN* rayN = RTCRayHitN_RayN(packet, N);
  RTCHitN* hitN = RTCRayHitN_HitN(packet, N);
  if (state_.callbacks) {
    for (unsigned i = 0; i < N; ++i) {
      if (!laneActive(valid, i)) continue;
      RTCRayHit rayhit = rtcGetRayHitFromRayHitN(packet, N, i);
      if (!intersect(rayhit)) continue;
      RTCRayN_tfar(rayN, N, i) = rayhit.ray.tfar;
      rtcCopyHitToHitN(hitN, &rayhit.hit, N, i);
    }
    return;
  }
  withPacketWidth(N, [&](auto width) {
    intersectInLaneGroups(valid, packet, width, masksOn_, nullptr, [&](Ray* rays, Hit* hits, uint32_t live) {
      return scene_.accel().intersectPacket(rays, hits, live, state_);
    });
  });
}

void QueryDispatch::occludedPacket(const int* valid, RTCRayN* rayN, unsigned N) {
  if (state_.callbacks) {
    for (unsigned i = 0; i < N; ++i) {
      if (!laneActive(valid, i)) continue;
      RTCRay ray = rtcGetRayFromRayN(rayN, N, i);
      if (occluded(ray)) RTCRayN_tfar(rayN, N, i) = ray.tfar;
    }
    return;
  }
  withPacketWidth(N, [&](auto width) {
    occludedInLaneGroups(valid, rayN, width, masksOn_,
                         [&](const Ray* rays, uint32_t live) { return scene_.accel().occludedPacket(rays, live, state_); });
  });
}

void QueryDispatch::runFilters(const Geometry& geometry, const RTCFilterFunctionNArguments* args,
                               bool occlusion) const {
  const RTCFilterFunctionN geometryFilter = occlusion ? geometry.occludedFilter() : geometry.intersectFilter();
  if (geometryFilter) geometryFilter(args);
  if (!state_.contextFilter) return;
  bool anyValid = false;
  for (unsigned i = 0; i < args->N; ++i) anyValid |= args->valid[i] != 0;
  if (anyValid) context_.filter(args);
}

bool QueryDispatch::acceptHit(const void* owner, const Ray& ray, const Hit& candidate, float t, bool occlusion) {
  const Scene& scene = *static_cast<const Scene*>(owner);
  const Geometry& geometry = *scene.builtGeometry(candidate.geomID);
  RTCRayHit rayhit;
  rayhit.ray = embreeRay(ray, t);
  rayhit.hit = embreeHit(candidate);
  int valid = -1;
  const RTCFilterFunctionNArguments args{&valid, geometry.userData(), &context_,
                                         reinterpret_cast<RTCRayN*>(&rayhit.ray),
                                         reinterpret_cast<RTCHitN*>(&rayhit.hit), 1};
  InstanceIdScope scope(context_, candidate.instID);
  runFilters(geometry, &args, occlusion);
  return valid != 0;
}

bool QueryDispatch::intersectUser(const void* owner, uint32_t geomID, uint32_t primID, Ray& ray, Hit& hit,
                                  const QueryState& state) {
  const Scene& scene = *static_cast<const Scene*>(owner);
  const Geometry& geometry = *scene.builtGeometry(geomID);
  if (!geometry.user().intersect) return false;
  RTCRayHit rayhit;
  rayhit.ray = embreeRay(ray, ray.tfar);
  rayhit.hit = embreeHit(hit);
  int valid = -1;
  UserIntersectArguments args;
  fillUserArguments(args, &valid, geometry, geomID, primID);
  args.rayhit = reinterpret_cast<RTCRayHitN*>(&rayhit);
  {
    InstanceIdScope scope(context_, state.instID);
    geometry.user().intersect(&args);
  }
  // The callback reports a hit by writing the ray's tfar and hit, as it would into Embree's ray.
  if (rayhit.ray.tfar == ray.tfar && rayhit.hit.geomID == hit.geomID && rayhit.hit.primID == hit.primID) return false;
  ray.tfar = rayhit.ray.tfar;
  hit = backendHit(rayhit.hit);
  return true;
}

bool QueryDispatch::occludedUser(const void* owner, uint32_t geomID, uint32_t primID, Ray& ray,
                                 const QueryState& state) {
  const Scene& scene = *static_cast<const Scene*>(owner);
  const Geometry& geometry = *scene.builtGeometry(geomID);
  if (!geometry.user().occluded) return false;
  RTCRay r = embreeRay(ray, ray.tfar);
  int valid = -1;
  UserOccludedArguments args;
  fillUserArguments(args, &valid, geometry, geomID, primID);
  args.ray = reinterpret_cast<RTCRayN*>(&r);
  {
    InstanceIdScope scope(context_, state.instID);
    geometry.user().occluded(&args);
  }
  return r.tfar == -std::numeric_limits<float>::infinity();
}

}  // namespace obvh::api

using namespace obvh::api;

// Called by user-geometry callbacks with the arguments obvh passed them (see UserIntersectArguments).
RTC_API void rtcFilterIntersection(const RTCIntersectFunctionNArguments* args,
                                   const RTCFilterFunctionNArguments* filterArgs) {
  if (!args || !filterArgs) return reportError(nullptr, RTC_ERROR_INVALID_ARGUMENT, "invalid argument");
  const auto* ours = static_cast<const UserIntersectArguments*>(args);
  ours->dispatch->runFilters(*ours->geometry, filterArgs, false);
}

RTC_API void rtcFilterOcclusion(const RTCOccludedFunctionNArguments* args,
                                const RTCFilterFunctionNArguments* filterArgs) {
  if (!args || !filterArgs) return reportError(nullptr, RTC_ERROR_INVALID_ARGUMENT, "invalid argument");
  const auto* ours = static_cast<const UserOccludedArguments*>(args);
  ours->dispatch->runFilters(*ours->geometry, filterArgs, true);
}
