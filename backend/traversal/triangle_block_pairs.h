// A packet's rays that reach a leaf: each is tested against the blocks' four triangles at a time
// (triangle_block_leaf.h), and two that share the watertight frame's axis order, as a coherent
// packet's rays do, are tested together: ray a in lanes 0-3 and ray b in lanes 4-7 of one
// eight-lane pass over each block (watertightBlockCandidatesOfPair), sharing the block's loads.
// Each ray still meets the blocks in order, with the same operations per lane and its own second
// half, so its answers are the single-ray test's, bit for bit.
// Templates only, included inside the per-ISA target regions like the kernels that use them.
#pragma once

#include <cstdint>
#include <type_traits>

#include "traversal/triangle_block_leaf.h"

namespace obvh {

// Whether the frames share their axis order (ky is the axis neither kx nor kz is).
[[gnu::always_inline]] inline bool sameAxisOrder(const WatertightRay& a, const WatertightRay& b) {
  return a.kx == b.kx && a.kz == b.kz;
}

// Goes through the rays of `mask` in order: pair(r, s, wa, wb) for a ray and the next one when they
// share the frame's axis order (wa, wb: frameOf(r), frameOf(s)), alone(r, wa) for the others. F8
// void (or pairing false) sends every ray alone.
template <typename F8, typename FrameOf, typename Pair, typename Alone>
[[gnu::always_inline]] inline void forRaysInPairs(uint32_t mask, bool pairing, FrameOf&& frameOf, Pair&& pair,
                                                  Alone&& alone) {
  while (mask) {
    const int r = __builtin_ctz(mask);
    mask &= mask - 1;
    const WatertightRay& wa = frameOf(r);
    if constexpr (!std::is_void_v<F8>) {
      if (mask != 0 && pairing) {
        const int s = __builtin_ctz(mask);
        const WatertightRay& wb = frameOf(s);
        if (sameAxisOrder(wa, wb)) {
          mask &= mask - 1;
          pair(r, s, wa, wb);
          continue;
        }
      }
    }
    alone(r, wa);
  }
}

// Closest hits of the rays of `mask` (rays[r], hits[r], frameOf(r) their watertight frames) against
// blockCount blocks from firstBlock; shrinks their tfar. Returns the rays that hit. F8: an
// eight-lane type for the pairs, or void to test every ray alone. kDropBehind: see visitBlockHits.
template <typename F4, typename F8, typename D4, bool kDropBehind, typename FrameOf>
[[gnu::always_inline]] inline uint32_t intersectBlocksClosestOfRays(const TriangleSet& set,
                                                                    const TriangleBlock4* blocks, uint32_t firstBlock,
                                                                    uint32_t blockCount, FrameOf&& frameOf, Ray* rays,
                                                                    Hit* hits, uint32_t mask, const QueryState& state) {
  uint32_t found = 0;
  // Generic, so that it is made only where F8 is a type (forRaysInPairs calls it).
  const auto pair = [&](int r, int s, const auto& wa, const auto& wb) __attribute__((always_inline)) {
    bool foundA = false, foundB = false;
    for (uint32_t b = firstBlock; b < firstBlock + blockCount; ++b) {
      const TriangleBlock4& block = blocks[b];
      BlockCandidates ca, cb;
      watertightBlockCandidatesOfPair<F8>(block, wa, wb, kDropBehind && !(rays[r].tnear < 0.f),
                                          kDropBehind && !(rays[s].tnear < 0.f), ca, cb);
      if (ca.resolve | ca.recheck)
        visitBlockCandidates<D4>(set, block, ca, wa, rays[r], closestHitVisitor(set, block, rays[r], hits[r], state, foundA));
      if (cb.resolve | cb.recheck)
        visitBlockCandidates<D4>(set, block, cb, wb, rays[s], closestHitVisitor(set, block, rays[s], hits[s], state, foundB));
    }
    found |= (uint32_t(foundA) << r) | (uint32_t(foundB) << s);
  };
  const auto alone = [&](int r, const WatertightRay& wa) __attribute__((always_inline)) {
    if (intersectBlocksClosest<F4, D4, kDropBehind>(set, blocks, firstBlock, blockCount, wa, rays[r], hits[r], state))
      found |= 1u << r;
  };
  forRaysInPairs<F8>(mask, !set.fast, frameOf, pair, alone);
  return found;
}

// The rays of `mask` that a triangle of the blocks blocks (and the filters accept), paired as
// intersectBlocksClosestOfRays pairs them.
template <typename F4, typename F8, typename D4, typename FrameOf>
[[gnu::always_inline]] inline uint32_t intersectBlocksAnyOfRays(const TriangleSet& set, const TriangleBlock4* blocks,
                                                                uint32_t firstBlock, uint32_t blockCount,
                                                                FrameOf&& frameOf, const Ray* rays, uint32_t mask,
                                                                const QueryState& state) {
  uint32_t blocked = 0;
  const auto pair = [&](int r, int s, const auto& wa, const auto& wb) __attribute__((always_inline)) {
    bool doneA = false, doneB = false;
    for (uint32_t b = firstBlock; b < firstBlock + blockCount && !(doneA && doneB); ++b) {
      const TriangleBlock4& block = blocks[b];
      BlockCandidates ca, cb;
      watertightBlockCandidatesOfPair<F8>(block, wa, wb, !(rays[r].tnear < 0.f), !(rays[s].tnear < 0.f), ca, cb);
      if (!doneA && (ca.resolve | ca.recheck))
        doneA = visitBlockCandidates<D4>(set, block, ca, wa, rays[r], anyHitVisitor(set, block, rays[r], state));
      if (!doneB && (cb.resolve | cb.recheck))
        doneB = visitBlockCandidates<D4>(set, block, cb, wb, rays[s], anyHitVisitor(set, block, rays[s], state));
    }
    blocked |= (uint32_t(doneA) << r) | (uint32_t(doneB) << s);
  };
  const auto alone = [&](int r, const WatertightRay& wa) __attribute__((always_inline)) {
    if (intersectBlocksAny<F4, D4>(set, blocks, firstBlock, blockCount, wa, rays[r], state)) blocked |= 1u << r;
  };
  forRaysInPairs<F8>(mask, !set.fast, frameOf, pair, alone);
  return blocked;
}

}  // namespace obvh
