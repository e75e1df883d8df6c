// Testing a leaf against a packet of rays that share the watertight test's axis order (kx, ky, kz,
// as coherent rays do): the rays are the SIMD lanes and the triangles come one at a time, in block
// and lane order. Each ray thus meets the triangles in the single-ray test's order, with the same
// edge-function operations (shearedEdges) and the same scalar second half, so its answers are
// bit-identical to the single-ray test's; the packet shares the triangle loads and tests up to
// eight rays in one pass where the single-ray test would run once per ray.
// Templates only (instantiated with each kernel file's own vector type): this header is included
// inside the per-ISA target regions, see wide_traversal_avx2.cpp.
#pragma once

#include <cstddef>
#include <cstdint>

#include "traversal/triangle_block_leaf.h"
#include "traversal/wide_traversal.h"

namespace obvh {

// The rays' origins in (kx, ky, kz) order and shear constants, as lanes of FR.
template <typename FR>
struct PacketShear {
  static constexpr int kLanes = FR::kWidth;
  alignas(32) float org[3][kMaxPacketSize];
  alignas(32) float Sx[kMaxPacketSize];
  alignas(32) float Sy[kMaxPacketSize];
  alignas(32) float Sz[kMaxPacketSize];
  int axes[3] = {0, 1, 2};
  int groups = 0;
  bool usable = false;  // every ray of the packet has the same axis order

  // The watertight frame's axis order and shear (WatertightRay) for every ray of live at once, the
  // same operations lane by lane (a division is exact, so each lane's Sx and Sy are the floats the
  // ray's own frame holds), where every live ray's frame used to be made and copied in lane by lane
  // (coherent rtcIntersect8 on the bunny: 497 -> 492 instructions a ray, 3% faster). rays must hold
  // the whole lane group of every ray of live (kMaxPacketSize entries do); idle lanes may be
  // uninitialized. Always inlined: compiled for the caller's instruction set (a test instantiating
  // it outside a target region otherwise gets a baseline copy of the eight-wide version, which the
  // linker may keep for everyone).
  [[gnu::always_inline]] PacketShear(const Ray* rays, uint32_t live) {
    if (live == 0) return;
    static_assert(offsetof(Ray, org) == 0 && offsetof(Ray, dir) == 4 * sizeof(float) &&
                      sizeof(Ray) % sizeof(float) == 0,
                  "a ray's first eight floats are org, tnear, dir (and time)");
    const int groupCount = (31 - __builtin_clz(live)) / kLanes + 1;
    const FR zero = FR::broadcast(0.f);
    FR leading[kMaxPacketSize / kLanes][8];  // org x, y, z, tnear, dir x, y, z, time of each group
    int dominant = -1, negative = -1;
    for (int g = 0; g < groupCount; ++g) {
      const int on = int((live >> (g * kLanes)) & ((1u << kLanes) - 1));
      for (int c = 0; c < 8; c += kLanes)
        FR::loadColumns(reinterpret_cast<const float*>(rays + g * kLanes) + c, sizeof(Ray) / sizeof(float),
                        leading[g] + c);
      if (on == 0) continue;
      const FR* dir = leading[g] + 4;
      // |dir| as WatertightRay's fabs: the larger of d and 0 - d (a NaN stays a NaN, -0 becomes +0).
      const FR ax = max(dir[0], zero - dir[0]), ay = max(dir[1], zero - dir[1]), az = max(dir[2], zero - dir[2]);
      // kz = (ax >= ay && ax >= az) ? 0 : (ay >= az ? 1 : 2), lane by lane.
      const int xDominates = lessEqualMask(ay, ax) & lessEqualMask(az, ax);
      const int yOverZ = lessEqualMask(az, ay);
      const int byAxis[3] = {xDominates, ~xDominates & yOverZ, ~xDominates & ~yOverZ};
      int kz = 0;
      while (kz < 2 && (byAxis[kz] & on) == 0) ++kz;
      if ((byAxis[kz] & on) != on || (dominant >= 0 && kz != dominant)) return;
      dominant = kz;
      const int below = lessMask(dir[kz], zero) & on;
      if ((below != 0 && below != on) || (negative >= 0 && int(below != 0) != negative)) return;
      negative = below != 0;
    }
    const int kz = dominant, kx = (kz + 1) % 3, ky = (kx + 1) % 3;
    axes[0] = negative ? ky : kx, axes[1] = negative ? kx : ky, axes[2] = kz;
    groups = groupCount;
    for (int g = 0; g < groupCount; ++g) {
      const int on = int((live >> (g * kLanes)) & ((1u << kLanes) - 1));
      const FR* dir = leading[g] + 4;
      const int base = g * kLanes;
      for (int a = 0; a < 3; ++a) select(on, leading[g][axes[a]], zero).store(org[a] + base);
      // Idle lanes divide 0 by 1.
      const FR divisor = select(on, dir[kz], FR::broadcast(1.f));
      (select(on, dir[axes[0]], zero) / divisor).store(Sx + base);
      (select(on, dir[axes[1]], zero) / divisor).store(Sy + base);
      (FR::broadcast(1.f) / divisor).store(Sz + base);
    }
    usable = true;
  }

  // Ray r's own watertight frame (WatertightRay(ray), the same floats) from a usable shear's lanes:
  // made from the ray instead, each candidate ray of a packet leaf cost its three divisions again
  // (about 100 instructions a coherent packet of eight).
  [[gnu::always_inline]] WatertightRay frame(const Ray& ray, int r) const {
    WatertightRay w;
    w.kx = axes[0], w.ky = axes[1], w.kz = axes[2];
    w.Sx = Sx[r], w.Sy = Sy[r], w.Sz = Sz[r];
    w.org = ray.org;
    return w;
  }
};

// Visits, for each triangle of the blocks in order and each ray of `rays` whose edge functions
// pass, the ray's candidate: visit(r, triangle, hit) returns true when ray r is done (any-hit), and
// it is then left out of the remaining triangles. Returns the rays that were done. frameOf(r) gives
// ray r's watertight frame (made when first asked for: only candidates need it).
template <typename FR, typename FrameOf, typename Visit>
[[gnu::always_inline]] inline uint32_t visitPacketHits(const TriangleSet& set, const TriangleBlock4* blocks,
                                                       uint32_t firstBlock, uint32_t blockCount,
                                                       const PacketShear<FR>& shear, FrameOf&& frameOf,
                                                       const Ray* rays, uint32_t active, Visit&& visit) {
  constexpr int kLanes = FR::kWidth;
  constexpr uint32_t kGroupBits = (1u << kLanes) - 1;
  uint32_t done = 0;
  for (uint32_t b = firstBlock; b < firstBlock + blockCount; ++b) {
    const TriangleBlock4& block = blocks[b];
    for (int triangles = block.usedLanes(); triangles; triangles &= triangles - 1) {
      const int t = __builtin_ctz(unsigned(triangles));
      FR vertex[3][3];
      for (int k = 0; k < 3; ++k)
        for (int a = 0; a < 3; ++a) vertex[k][a] = FR::broadcast(block.v[k][shear.axes[a]][t]);
      const uint32_t triangleMask = set.geometryMasks[block.geomID[t]];
      for (int g = 0; g < shear.groups; ++g) {
        const int base = g * kLanes;
        const uint32_t groupRays = ((active & ~done) >> base) & kGroupBits;
        if (groupRays == 0) continue;
        const FR org[3] = {FR::load(shear.org[0] + base), FR::load(shear.org[1] + base), FR::load(shear.org[2] + base)};
        const ShearedEdges<FR> e = shearedEdges(vertex, org, FR::load(shear.Sx + base), FR::load(shear.Sy + base));
        const EdgeVerdict verdict = judgeEdges(e, int(groupRays));
        int candidates = verdict.resolve | verdict.recheck;
        if (candidates == 0) continue;
        alignas(32) float U[kLanes], V[kLanes], W[kLanes];
        e.U.store(U);
        e.V.store(V);
        e.W.store(W);
        const StoredTriangle tri = block.triangle(t);
        for (; candidates; candidates &= candidates - 1) {
          const int lane = __builtin_ctz(unsigned(candidates));
          const int r = base + lane;
          if ((triangleMask & rays[r].mask) == 0) continue;
          TriangleHit th;
          const bool hit = (verdict.recheck >> lane) & 1
                               ? intersectWatertight(frameOf(r), rays[r], tri.v0, tri.v1, tri.v2, th)
                               : resolveWatertightHit([&]() -> const WatertightRay& { return frameOf(r); }, rays[r],
                                                      tri.v0, tri.v1, tri.v2, U[lane], V[lane], W[lane], th);
          if (hit && visit(r, tri, th)) done |= 1u << r;
        }
      }
    }
  }
  return done;
}

// Closest hits of the packet's rays in `active`; shrinks their tfar. Returns the rays that hit.
template <typename FR, typename FrameOf>
inline uint32_t intersectBlocksClosestPacket(const TriangleSet& set, const TriangleBlock4* blocks, uint32_t firstBlock,
                                             uint32_t blockCount, const PacketShear<FR>& shear,
                                             FrameOf&& frameOf, Ray* rays, Hit* hits, uint32_t active,
                                             const QueryState& state) {
  uint32_t found = 0;
  visitPacketHits<FR>(set, blocks, firstBlock, blockCount, shear, frameOf, rays, active,
                      [&](int r, const StoredTriangle& tri, const TriangleHit& th) {
                        const Hit candidate = makeTriangleHit(set, tri, th, state.instID);
                        if (needsFilter(set.intersectFiltered, tri.geomID, state) &&
                            !state.callbacks->acceptHit(set.owner, rays[r], candidate, th.t, false))
                          return false;
                        rays[r].tfar = th.t;
                        hits[r] = candidate;
                        found |= 1u << r;
                        return false;
                      });
  return found;
}

// The rays of `active` that a triangle of the blocks occludes (and the filters accept).
template <typename FR, typename FrameOf>
inline uint32_t intersectBlocksAnyPacket(const TriangleSet& set, const TriangleBlock4* blocks, uint32_t firstBlock,
                                         uint32_t blockCount, const PacketShear<FR>& shear,
                                         FrameOf&& frameOf, const Ray* rays, uint32_t active,
                                         const QueryState& state) {
  return visitPacketHits<FR>(set, blocks, firstBlock, blockCount, shear, frameOf, rays, active,
                             [&](int r, const StoredTriangle& tri, const TriangleHit& th) {
                               return !needsFilter(set.occlusionFiltered, tri.geomID, state) ||
                                      state.callbacks->acceptHit(set.owner, rays[r],
                                                                 makeTriangleHit(set, tri, th, state.instID), th.t, true);
                             });
}

}  // namespace obvh
