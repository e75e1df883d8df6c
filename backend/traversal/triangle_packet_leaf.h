// Testing a leaf against a packet of rays that share the watertight test's axis order (kx, ky, kz,
// as coherent rays do): the rays are the SIMD lanes and the triangles come one at a time, in block
// and lane order. Each ray thus meets the triangles in the single-ray test's order, with the same
// edge-function operations (shearedEdges) and the same scalar second half, so its answers are
// bit-identical to the single-ray test's; the packet shares the triangle loads and tests up to
// eight rays in one pass where the single-ray test would run once per ray.
// Templates only (instantiated with each kernel file's own vector type): this header is included
// inside the per-ISA target regions, see wide_traversal_avx2.cpp.
#pragma once

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
  int axes[3] = {0, 1, 2};
  int groups = 0;
  bool usable = false;  // every ray of the packet has the same axis order

  // frames[r] must be made for every ray r in live.
  PacketShear(const WatertightRay* frames, uint32_t live) {
    if (live == 0) return;
    const WatertightRay& first = frames[__builtin_ctz(live)];
    for (uint32_t m = live; m; m &= m - 1) {
      const WatertightRay& f = frames[__builtin_ctz(m)];
      if (f.kx != first.kx || f.ky != first.ky || f.kz != first.kz) return;
    }
    axes[0] = first.kx, axes[1] = first.ky, axes[2] = first.kz;
    groups = (31 - __builtin_clz(live)) / kLanes + 1;
    for (int r = 0; r < groups * kLanes; ++r) {
      const bool on = (live >> r) & 1;
      for (int a = 0; a < 3; ++a) org[a][r] = on ? frames[r].org[axes[a]] : 0.f;
      Sx[r] = on ? frames[r].Sx : 0.f;
      Sy[r] = on ? frames[r].Sy : 0.f;
    }
    usable = true;
  }
};

// Visits, for each triangle of the blocks in order and each ray of `rays` whose edge functions
// pass, the ray's candidate: visit(r, triangle, hit) returns true when ray r is done (any-hit), and
// it is then left out of the remaining triangles. Returns the rays that were done.
template <typename FR, typename Visit>
[[gnu::always_inline]] inline uint32_t visitPacketHits(const TriangleSet& set, const TriangleBlock4* blocks,
                                                       uint32_t firstBlock, uint32_t blockCount,
                                                       const PacketShear<FR>& shear, const WatertightRay* frames,
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
                               ? intersectWatertight(frames[r], rays[r], tri.v0, tri.v1, tri.v2, th)
                               : resolveWatertightHit(frames[r], rays[r], tri.v0, tri.v1, tri.v2, U[lane], V[lane],
                                                      W[lane], th);
          if (hit && visit(r, tri, th)) done |= 1u << r;
        }
      }
    }
  }
  return done;
}

// Closest hits of the packet's rays in `active`; shrinks their tfar. Returns the rays that hit.
template <typename FR>
inline uint32_t intersectBlocksClosestPacket(const TriangleSet& set, const TriangleBlock4* blocks, uint32_t firstBlock,
                                             uint32_t blockCount, const PacketShear<FR>& shear,
                                             const WatertightRay* frames, Ray* rays, Hit* hits, uint32_t active,
                                             const QueryState& state) {
  uint32_t found = 0;
  visitPacketHits<FR>(set, blocks, firstBlock, blockCount, shear, frames, rays, active,
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
template <typename FR>
inline uint32_t intersectBlocksAnyPacket(const TriangleSet& set, const TriangleBlock4* blocks, uint32_t firstBlock,
                                         uint32_t blockCount, const PacketShear<FR>& shear,
                                         const WatertightRay* frames, const Ray* rays, uint32_t active,
                                         const QueryState& state) {
  return visitPacketHits<FR>(set, blocks, firstBlock, blockCount, shear, frames, rays, active,
                             [&](int r, const StoredTriangle& tri, const TriangleHit& th) {
                               return !needsFilter(set.occlusionFiltered, tri.geomID, state) ||
                                      state.callbacks->acceptHit(set.owner, rays[r],
                                                                 makeTriangleHit(set, tri, th, state.instID), th.t, true);
                             });
}

}  // namespace obvh
