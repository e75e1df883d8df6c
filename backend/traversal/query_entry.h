// A committed scene's queries reduced to what rtcIntersect1/rtcOccluded1 and the packet queries
// need at every call: the structure to trace and the kernels to trace it with, chosen once at
// commit. Chosen per ray (the layout, whether its tree is empty, then the coherence hint) they took
// about ten instructions of rtcIntersect1's own 63 a bunny camera ray (callgrind; Embree's
// rtcIntersect1 runs 23 of its own).
#pragma once

#include <cstdint>

#include "intersect/ray.h"
#include "traversal/query_callbacks.h"

namespace obvh {

// The box around the root node's children of an axis-aligned wide tree, which a packet's lanes
// are tested against first (packet_gate.h). `bounded` is false for other structures and for a
// tree whose root is a leaf: no lane is then turned away.
struct PacketGate {
  bool bounded = false;
  float lower[3] = {0.f, 0.f, 0.f};
  float upper[3] = {0.f, 0.f, 0.f};
};

struct QueryEntry {
  using Closest = bool (*)(const void* target, Ray& ray, Hit& hit, const QueryState& state);
  using Any = bool (*)(const void* target, const Ray& ray, const QueryState& state);
  // Packets of up to kMaxPacketSize rays, as the wide kernels take them (traversal/wide_traversal.h):
  // the mask of the active lanes that hit / are occluded.
  using ClosestPacket = uint32_t (*)(const void* target, Ray* rays, Hit* hits, uint32_t active,
                                     const QueryState& state);
  using AnyPacket = uint32_t (*)(const void* target, const Ray* rays, uint32_t active, const QueryState& state);

  const void* target = nullptr;  // what the kernels trace (a layout's view, or the scene's structure)
  // Indexed by QueryState::coherent: the walk for incoherent rays, then the one for coherent rays.
  // The state passed must not count (QueryState::counters null).
  Closest closest[2] = {&missesAll, &missesAll};
  Any any[2] = {&blocksNothing, &blocksNothing};
  ClosestPacket closestPacket = &packetMissesAll;
  AnyPacket anyPacket = &packetBlocksNothing;
  PacketGate packetGate;

  // coherent: state.coherent, passed by callers that know it without loading it from the state.
  bool intersect(Ray& ray, Hit& hit, const QueryState& state, bool coherent) const {
    return closest[coherent](target, ray, hit, state);
  }
  bool occluded(const Ray& ray, const QueryState& state, bool coherent) const {
    return any[coherent](target, ray, state);
  }

  // An empty structure's kernels.
  static bool missesAll(const void*, Ray&, Hit&, const QueryState&) { return false; }
  static bool blocksNothing(const void*, const Ray&, const QueryState&) { return false; }
  static uint32_t packetMissesAll(const void*, Ray*, Hit*, uint32_t, const QueryState&) { return 0; }
  static uint32_t packetBlocksNothing(const void*, const Ray*, uint32_t, const QueryState&) { return 0; }
};

}  // namespace obvh
