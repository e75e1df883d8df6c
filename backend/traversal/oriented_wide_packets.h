// Closest-hit packet traversal of the eight-wide oriented layouts (rtcIntersect4/8/16 and streams
// with accel=obb|hybrid): the rays of a packet share node loads, one stack and one near-to-far
// order, while every child-box decision is the single ray's. A child's box is tested
// against a lane group of rays at once by the single-ray test itself (enterBoxLanes), the lanes
// being rays instead of children;
// each ray's origin and inverse direction in the palette's frames are made once a packet, and for
// rays of a common direction (an orthographic camera) the direction's transform is made once for
// all of them. Leaves test the rays that reach them as the wide AABB layouts' packets do, two rays
// to a block test where they can (triangle_block_pairs.h), and a ray left alone below a node
// finishes with the single-ray walk. A ray's answer is thus its own, but for which of several
// hits at exactly the same distance it reports: the packet visits leaves in its order (and may
// take a ray into a leaf it alone would have skipped for starting at its hit's distance), and
// the last of equal hits stands. Occlusion packets are traced ray by ray: together, the
// shadow rays of obvh_bench's views traced 13-18% slower on small-1.5k and diagonal-42k (their
// origins spread over the stack; README, layout study).
// Included only by the AVX2 translation unit, inside its target region.
#pragma once

#include <cstdint>
#include <cstring>
#include <limits>

#include "traversal/oriented_wide_traverse.h"
#include "traversal/wide_traverse_packets.h"

namespace obvh {

// Nodes reached by at most kOrientedSoloRays rays let them go on alone (one, two or three measured
// alike, within 2%). Until 2026-11-30 leaves reached by four rays or more (and three quarters of a
// lane group) tested them as the lanes of each triangle's test; against the pairs, with that
// dropped: accel=hybrid bunny 1.03, small-1.5k 1.05-1.07, diagonal-42k 0.99-1.02, mixed-654k
// 1.02; accel=obb small-1.5k 1.06-1.07, diagonal-42k 0.99-1.01, mixed-654k 1.01-1.02 (paired
// probe, rtcIntersect8 camera and orthographic packets).
constexpr int kOrientedSoloRays = 3;

// The packet's rays as lanes (FN::kWidth rays a group), in world space and in every palette slot.
template <typename FN>
struct OrientedPacketRays {
  static constexpr int kLanes = FN::kWidth;
  static constexpr int kSlots = FramePalette::kSlots;
  alignas(32) float org[3][kMaxPacketSize];
  alignas(32) float dir[3][kMaxPacketSize];
  alignas(32) float slotOrg[kSlots][3][kMaxPacketSize];
  alignas(32) float slotInv[kSlots][3][kMaxPacketSize];
  alignas(32) float originNorm[kMaxPacketSize];
  alignas(32) float tnear[kMaxPacketSize];
  alignas(32) float limit[kMaxPacketSize];  // each ray's walk limit (walkWideTree's `limit`)
  float initialTfar[kMaxPacketSize];
  int groups = 0;
  bool commonDirection = false;
  bool usePalette = false;  // nodes with inPalette take the slots' lanes (a palette tree's only)
  bool sameSigns = false;   // the rays' directions have the same signs and every value is a number:
                            // the rays may travel together
  // The packet in every palette slot (slots as lanes), for one pass over a palette node's children
  // that leaves out those no ray can enter (mayEnter): the range of the rays' origins and inverse
  // directions along each row, and per row the slots whose inverse direction is infinite for
  // every ray (a common direction within a frame plane) or has no usable range.
  FN boundOrgLow[3], boundOrgHigh[3], boundInvLow[3], boundInvHigh[3];
  FN infiniteSlots[3], unboundedSlots[3];  // -1 in the slots meant, 0 elsewhere
  float originNormHigh = 0.f, tnearLow = 0.f, limitHigh = 0.f;
  uint32_t liveRays = 0;

  OrientedPacketRays(const OrientedWideBvh<kLanes>& bvh, const Ray* rays, uint32_t live) {
    groups = live ? (31 - __builtin_clz(live)) / kLanes + 1 : 0;
    const int used = groups * kLanes;
    const int first = live ? __builtin_ctz(live) : 0;
    commonDirection = sameSigns = live != 0;
    for (int r = 0; r < used; ++r) {
      const bool on = (live >> r) & 1;
      const Ray& ray = rays[on ? r : first];
      for (int a = 0; a < 3; ++a) org[a][r] = ray.org[a], dir[a][r] = ray.dir[a];
      originNorm[r] = std::fabs(ray.org.x) + std::fabs(ray.org.y) + std::fabs(ray.org.z);
      tnear[r] = on ? ray.tnear : std::numeric_limits<float>::infinity();
      initialTfar[r] = limit[r] = on ? ray.tfar : -std::numeric_limits<float>::infinity();
      if (on && std::memcmp(&ray.dir, &rays[first].dir, sizeof ray.dir) != 0) commonDirection = false;
      for (int a = 0; a < 3; ++a)
        if (on && std::signbit(ray.dir[a]) != std::signbit(rays[first].dir[a])) sameSigns = false;
      // A ray without numbers (which enters no box alone) would spoil the packet's bounds.
      if (on && !(std::isfinite(ray.org.x) && std::isfinite(ray.org.y) && std::isfinite(ray.org.z) &&
                  std::isfinite(ray.dir.x) && std::isfinite(ray.dir.y) && std::isfinite(ray.dir.z) &&
                  !std::isnan(ray.tnear) && !std::isnan(ray.tfar)))
        sameSigns = false;
    }
    liveRays = live;
    if (!sameSigns) return;
    usePalette = bvh.hasPalette;
    if (!usePalette) return;
    // The palette's rows as rayAlongRow takes them, one operand a slot, broadcast over the rays.
    if (commonDirection) {
      // One ray's transform into every slot (slots as lanes, as the single-ray PaletteRay), then
      // each slot's inverse direction spread over the rays.
      const OrientedWideRay<FN> one(rays[first]);
      const PaletteRay<FN> p(one, bvh.palette);
      for (int row = 0; row < 3; ++row) {
        alignas(32) float inv[kSlots];
        p.inv[row].store(inv);
        for (int s = 0; s < kSlots; ++s)
          for (int g = 0; g < groups; ++g) FN::broadcast(inv[s]).store(slotInv[s][row] + g * kLanes);
      }
    }
    float orgLow[3], orgHigh[3], dirLow[3], dirHigh[3];
    for (int a = 0; a < 3; ++a) {
      orgLow[a] = dirLow[a] = std::numeric_limits<float>::infinity();
      orgHigh[a] = dirHigh[a] = -std::numeric_limits<float>::infinity();
    }
    originNormHigh = tnearLow = std::numeric_limits<float>::infinity();
    const FN zero = FN::broadcast(0.f);
    const auto highestOf = [&](const FN& x, int on) { return 0.f - minOfLanes(zero - x, on); };
    for (int g = 0; g < groups; ++g) {
      const int base = g * kLanes;
      const int on = int((live >> base) & ((1u << kLanes) - 1));
      if (on == 0) continue;
      for (int a = 0; a < 3; ++a) {
        orgLow[a] = std::min(orgLow[a], minOfLanes(FN::load(org[a] + base), on));
        orgHigh[a] = std::max(orgHigh[a], highestOf(FN::load(org[a] + base), on));
        dirLow[a] = std::min(dirLow[a], minOfLanes(FN::load(dir[a] + base), on));
        dirHigh[a] = std::max(dirHigh[a], highestOf(FN::load(dir[a] + base), on));
      }
      originNormHigh = std::min(originNormHigh, minOfLanes(zero - FN::load(originNorm + base), on));
      tnearLow = std::min(tnearLow, minOfLanes(FN::load(tnear + base), on));
    }
    originNormHigh = 0.f - originNormHigh;
    refreshLimitHigh();
    for (int row = 0; row < 3; ++row) {
      // Each ray's row value a0 o0 + a1 o1 + a2 o2, rounded, lies between the same sums of the
      // products' smallest (largest) corners: rounding is monotone in every operand.
      const FN a[3] = {FN::load(bvh.palette.axis[row][0]), FN::load(bvh.palette.axis[row][1]),
                       FN::load(bvh.palette.axis[row][2])};
      FN low[2], high[2];  // origin, direction
      for (int which = 0; which < 2; ++which) {
        const float* l = which == 0 ? orgLow : dirLow;
        const float* h = which == 0 ? orgHigh : dirHigh;
        FN sumLow, sumHigh;
        for (int k = 0; k < 3; ++k) {
          const FN p = a[k] * FN::broadcast(l[k]), q = a[k] * FN::broadcast(h[k]);
          sumLow = k == 0 ? min(p, q) : sumLow + min(p, q);
          sumHigh = k == 0 ? max(p, q) : sumHigh + max(p, q);
        }
        low[which] = sumLow, high[which] = sumHigh;
      }
      boundOrgLow[row] = low[0], boundOrgHigh[row] = high[0];
      const FN one = FN::broadcast(1.f);
      const FN largest = FN::broadcast(std::numeric_limits<float>::max());
      const auto finite = [&](const FN& x) { return lessEqualMask(x, largest) & lessEqualMask(zero - largest, x); };
      if (commonDirection) {
        // Every ray's inverse direction is the one computed above, exactly.
        alignas(32) float inv[kSlots];
        for (int s = 0; s < kSlots; ++s) inv[s] = slotInv[s][row][first];
        const FN exact = FN::load(inv);
        const int infinite = ~finite(exact);
        infiniteSlots[row] = select(infinite, zero - one, zero);
        unboundedSlots[row] = zero;
        boundInvLow[row] = boundInvHigh[row] = exact;
      } else {
        // 1/x is monotone on either side of zero; a range that reaches zero bounds nothing, nor
        // does one whose inverse overflows (a ray on a slab's plane would make the bounds NaN).
        boundInvLow[row] = one / high[1];
        boundInvHigh[row] = one / low[1];
        const int usable =
            (lessMask(zero, low[1]) | lessMask(high[1], zero)) & finite(boundInvLow[row]) & finite(boundInvHigh[row]);
        infiniteSlots[row] = zero;
        unboundedSlots[row] = select(~usable, zero - one, zero);
      }
    }
    for (int g = 0; g < groups; ++g) {
      const int base = g * kLanes;
      const FN o[3] = {FN::load(org[0] + base), FN::load(org[1] + base), FN::load(org[2] + base)};
      const FN d[3] = {FN::load(dir[0] + base), FN::load(dir[1] + base), FN::load(dir[2] + base)};
      for (int s = 0; s < kSlots; ++s)
        for (int row = 0; row < 3; ++row) {
          const FN a0 = FN::broadcast(bvh.palette.axis[row][0][s]), a1 = FN::broadcast(bvh.palette.axis[row][1][s]),
                   a2 = FN::broadcast(bvh.palette.axis[row][2][s]);
          if (commonDirection) {
            alongRow(a0, a1, a2, o).store(slotOrg[s][row] + base);
          } else {
            FN ro, inv;
            rayAlongRow(a0, a1, a2, o, d, ro, inv);
            ro.store(slotOrg[s][row] + base);
            inv.store(slotInv[s][row] + base);
          }
        }
    }
  }

  // The children of a palette node that some ray may enter: one pass over all of them with the
  // packet's bounds (every step monotone, so the bounds hold for the values each ray computes);
  // a node of per-child frames gets no such pass.
  template <int N>
  [[gnu::always_inline]] int mayEnter(const OrientedWideNode<N>& node) const {
    static_assert(N == kLanes, "one lane a child");
    if (!(usePalette && node.inPalette)) return node.usedMask;
    const FN inf = FN::broadcast(std::numeric_limits<float>::infinity()), minusInf = FN::broadcast(0.f) - inf;
    const FN margin = FN::load(node.oriented) * FN::broadcast(2.f * kObbMarginScale) *
                      (FN::broadcast(originNormHigh) + FN::load(node.magnitude));
    FN nearLow = FN::broadcast(tnearLow), farHigh = inf;
    for (int row = 0; row < 3; ++row) {
      const FN oLow = lanesAt(boundOrgLow[row], node.paletteSlot), oHigh = lanesAt(boundOrgHigh[row], node.paletteSlot);
      const FN iLow = lanesAt(boundInvLow[row], node.paletteSlot), iHigh = lanesAt(boundInvHigh[row], node.paletteSlot);
      const FN lo = FN::load(node.lower[row]) - margin, hi = FN::load(node.upper[row]) + margin;
      const FN d[4] = {lo - oHigh, lo - oLow, hi - oHigh, hi - oLow};
      FN rowLow = min(d[0] * iLow, d[0] * iHigh), rowHigh = max(d[0] * iLow, d[0] * iHigh);
      for (int k = 1; k < 4; ++k) {
        rowLow = min(rowLow, min(d[k] * iLow, d[k] * iHigh));
        rowHigh = max(rowHigh, max(d[k] * iLow, d[k] * iHigh));
      }
      // Rays that do not move along the row: inside the slab where their origins are.
      const FN none = FN::broadcast(0.f);
      const int infinite = lessMask(lanesAt(infiniteSlots[row], node.paletteSlot), none);
      const int overlaps = lessEqualMask(lo, oHigh) & lessEqualMask(oLow, hi);
      rowLow = select(infinite, select(overlaps, minusInf, inf), rowLow);
      rowHigh = select(infinite, inf, rowHigh);
      const int unbounded = lessMask(lanesAt(unboundedSlots[row], node.paletteSlot), none);
      rowLow = select(unbounded, minusInf, rowLow);
      rowHigh = select(unbounded, inf, rowHigh);
      nearLow = max(nearLow, rowLow);
      farHigh = min(farHigh, rowHigh);
    }
    farHigh = min(farHigh * FN::broadcast(kConservativeFarScale), FN::broadcast(limitHigh));
    return lessEqualMask(nearLow, farHigh) & node.usedMask;
  }

  // The rays of groupRays (bits of lane group g) entering child c of node, with their entry
  // distances: the single-ray node test for child c, lane by lane over the rays.
  template <int N>
  [[gnu::always_inline]] int enterChild(const OrientedWideNode<N>& node, int c, int g, int groupRays,
                                        FN& nearT) const {
    const int base = g * kLanes;
    const int slot = node.paletteSlot[c];
    const bool fromPalette = usePalette && node.inPalette;
    const int entered = enterBoxLanes(
        FN::broadcast(node.oriented[c]), FN::broadcast(node.magnitude[c]), FN::load(originNorm + base),
        FN::load(tnear + base), FN::load(limit + base),
        [&](int row) { return FN::broadcast(node.lower[row][c]); },
        [&](int row) { return FN::broadcast(node.upper[row][c]); },
        [&](int row, FN& o, FN& inv) {
          if (fromPalette) {
            o = FN::load(slotOrg[slot][row] + base);
            inv = FN::load(slotInv[slot][row] + base);
            return;
          }
          const FN ro[3] = {FN::load(org[0] + base), FN::load(org[1] + base), FN::load(org[2] + base)};
          const FN rd[3] = {FN::load(dir[0] + base), FN::load(dir[1] + base), FN::load(dir[2] + base)};
          rayAlongRow(FN::broadcast(node.axis[row][0][c]), FN::broadcast(node.axis[row][1][c]),
                      FN::broadcast(node.axis[row][2][c]), ro, rd, o, inv);
        },
        nearT);
    return entered & groupRays;
  }

  // The rays of `rays` whose limit lies before t (the single walk would skip an entry at t).
  // kGroups: groups, as a constant (walkOrientedPacket's).
  template <int kGroups>
  uint32_t raysEndingBefore(float t, uint32_t rays) const {
    uint32_t ending = 0;
    for (int g = 0; g < kGroups; ++g)
      if ((rays >> (g * kLanes)) & ((1u << kLanes) - 1))
        ending |= uint32_t(lessMask(FN::load(limit + g * kLanes), FN::broadcast(t))) << (g * kLanes);
    return ending & rays;
  }

  // After a leaf: the limits of the rays that may have shrunk their tfar, as walkWideTree sets it.
  template <int kGroups>
  void refreshLimits(const Ray* rays, uint32_t changed) {
    for (; changed; changed &= changed - 1) {
      const int r = __builtin_ctz(changed);
      limit[r] = rays[r].tfar < initialTfar[r] ? nextFloatDown(rays[r].tfar) : rays[r].tfar;
    }
    refreshLimitHigh<kGroups>();
  }

 private:
  // kGroups: groups, or 0 for a count known only at run time.
  template <int kGroups = 0>
  void refreshLimitHigh() {
    float negatedHigh = std::numeric_limits<float>::infinity();
    for (int g = 0; g < (kGroups ? kGroups : groups); ++g) {
      const int on = int((liveRays >> (g * kLanes)) & ((1u << kLanes) - 1));
      if (on) negatedHigh = std::min(negatedHigh, minOfLanes(FN::broadcast(0.f) - FN::load(limit + g * kLanes), on));
    }
    limitHigh = 0.f - negatedHigh;
  }
};

// The packet's walk: children near to far by the smallest entry among the rays entering them (the
// lower lane first on ties, as the single-ray walk), rays dropped where their limit ends.
// leafVisitor(firstBlock, blockCount, rays) and soloVisitor(node, rays) return the rays whose
// segment they shortened (a hit): only those take their new limit (as walkWidePacket's closest-hit
// walk).
// kGroups: lanes.groups, as a constant (the loops over the groups unroll).
template <typename FN, int kGroups, typename LeafVisitor, typename SoloVisitor>
void walkOrientedPacketOf(const OrientedWideBvh<FN::kWidth>& bvh, OrientedPacketRays<FN>& lanes, const Ray* rays,
                          uint32_t active, LeafVisitor&& leafVisitor, SoloVisitor&& soloVisitor) {
  constexpr int N = FN::kWidth;
  using Codes = WideNode<N>;
  struct Entry {
    uint32_t child;
    uint32_t rays;
    float t;  // the smallest entry distance of these rays
  };
  // Rays going different ways share little of their paths, and alone each visits its leaves in
  // its own order, which decides among hits at exactly the same distance as the single-ray
  // kernels do (incoherent packets then answer bit for bit as their rays alone). So do packets
  // holding a ray with NaN or infinite values.
  if (!lanes.sameSigns) {
    soloVisitor(bvh.rootChild, active);
    return;
  }
  Entry stack[(N - 1) * 128];
  int top = 0;
  uint32_t current = bvh.rootChild, currentRays = active;
  for (;;) {
    while (currentRays) {
      if (Codes::isLeaf(current)) {
        const uint32_t shortened =
            leafVisitor(Codes::leafFirstBlock(current), Codes::leafBlockCount(current), currentRays);
        if (shortened) lanes.template refreshLimits<kGroups>(rays, shortened);
        break;
      }
      if (__builtin_popcount(currentRays) <= kOrientedSoloRays) {
        const uint32_t shortened = soloVisitor(current, currentRays);
        if (shortened) lanes.template refreshLimits<kGroups>(rays, shortened);
        break;
      }
      const OrientedWideNode<N>& node = bvh.nodes[current];
      // The entered children, near to far.
      Entry next[N];
      int n = 0;
      for (int candidates = lanes.mayEnter(node); candidates; candidates &= candidates - 1) {
        const int c = __builtin_ctz(unsigned(candidates));
        Entry e{node.child[c], 0u, std::numeric_limits<float>::infinity()};
        for (int g = 0; g < kGroups; ++g) {
          const int groupRays = int((currentRays >> (g * FN::kWidth)) & ((1u << FN::kWidth) - 1));
          if (groupRays == 0) continue;
          FN nearT;
          const int in = lanes.enterChild(node, c, g, groupRays, nearT);
          if (in == 0) continue;
          e.t = std::min(e.t, minOfLanes(nearT, in));
          e.rays |= uint32_t(in) << (g * FN::kWidth);
        }
        if (e.rays == 0) continue;
        if (!Codes::isLeaf(e.child)) {
          // The five cache lines a palette node's test reads: without, mixed-654k's packets traced
          // 10-15% slower (their nodes' loads are not hidden behind a predicted lane, as a single
          // ray's are).
          const char* line = reinterpret_cast<const char*>(&bvh.nodes[e.child]);
          for (int l = 0; l < 5; ++l) __builtin_prefetch(line + 64 * l);
        }
        int k = n++;
        while (k > 0 && next[k - 1].t > e.t) {
          next[k] = next[k - 1];
          --k;
        }
        next[k] = e;
      }
      if (n == 0) break;
      for (int k = n - 1; k >= 1; --k) stack[top++] = next[k];
      current = next[0].child;
      currentRays = next[0].rays & active;
    }
    if (top == 0) return;
    const Entry e = stack[--top];
    current = e.child;
    currentRays = e.rays & active;
    currentRays &= ~lanes.template raysEndingBefore<kGroups>(e.t, currentRays);
  }
}

// walkOrientedPacketOf for the lanes' number of groups (diagonal-42k with accel=obb, coherent
// rtcIntersect8: 988 -> 925 instructions a ray, callgrind; closest-hit packets 1.006-1.029x as fast
// there and on the bunny).
template <typename FN, typename LeafVisitor, typename SoloVisitor>
void walkOrientedPacket(const OrientedWideBvh<FN::kWidth>& bvh, OrientedPacketRays<FN>& lanes, const Ray* rays,
                        uint32_t active, LeafVisitor&& leafVisitor, SoloVisitor&& soloVisitor) {
  withGroupCount<kMaxPacketSize / FN::kWidth>(lanes.groups, [&](auto groups) {
    walkOrientedPacketOf<FN, decltype(groups)::value>(bvh, lanes, rays, active, leafVisitor, soloVisitor);
  });
}

// The rays of `active` worth tracing: a segment that is not empty and meets the tree's bounds.
template <typename F4, int N>
uint32_t raysPassingGate(const TriangleOrientedWideView<N>& view, const Ray* rays, uint32_t active) {
  uint32_t live = 0;
  for (uint32_t m = active; m; m &= m - 1) {
    const int r = __builtin_ctz(m);
    if (!(rays[r].tnear > rays[r].tfar) && mayEnterBox<F4>(view.gate, rays[r])) live |= 1u << r;
  }
  return live;
}

// One ray from `start` down, as the single-ray closest-hit kernel walks it.
template <typename FN, typename LeafVisitor>
void walkOrientedAlone(const TriangleOrientedWideView<FN::kWidth>& view, uint32_t start, const Ray& ray,
                       LeafVisitor&& leafVisitor) {
  const OrientedWideBvh<FN::kWidth>& bvh = *view.bvh;
  const OrientedWideRay<FN> r(ray);
  if (bvh.hasPalette) {
    const PaletteRay<FN> p(r, bvh.palette);
    walkWideTree<FN::kWidth, true, false>(PaletteWideNodes<FN>{bvh, r, p}, start, ray, leafVisitor, nullptr);
  } else {
    walkWideTree<FN::kWidth, true, false>(OrientedWideNodes<FN>{bvh, r}, start, ray, leafVisitor, nullptr);
  }
}

template <typename FN, typename F4>
uint32_t intersectClosestOrientedWidePacketImpl(const TriangleOrientedWideView<FN::kWidth>& view, Ray* rays,
                                                Hit* hits, uint32_t active, const QueryState& state) {
  const OrientedWideBvh<FN::kWidth>& bvh = *view.bvh;
  if (view.empty()) return 0;
  const uint32_t live = raysPassingGate<F4>(view, rays, active);
  if (live == 0) return 0;
  PacketFrames<FN> f(live);
  uint32_t found = 0;
  // The leaf and solo visits return the rays they found a hit for (walkOrientedPacketOf).
  const auto blocksAlone = [&](uint32_t firstBlock, uint32_t blockCount, int r) {
    return intersectBlocksClosest<F4, simd::DoubleLanes<FN>>(view.set, bvh.blocks.data(), firstBlock, blockCount,
                                                             f.triangleFrame(rays, r), rays[r], hits[r], state);
  };
  const auto leaf = [&](uint32_t firstBlock, uint32_t blockCount, uint32_t mask) {
    f.prepare(rays, mask);
    const uint32_t hit = intersectBlocksClosestOfRays<F4, PairLanes<FN>, simd::DoubleLanes<FN>, true>(
        view.set, bvh.blocks.data(), firstBlock, blockCount, f.preparedFrames(), rays, hits, mask, state);
    found |= hit;
    return hit;
  };
  const auto solo = [&](uint32_t node, uint32_t mask) {
    uint32_t hit = 0;
    for (; mask; mask &= mask - 1) {
      const int r = __builtin_ctz(mask);
      walkOrientedAlone<FN>(view, node, rays[r], [&](uint32_t firstBlock, uint32_t blockCount) {
        const bool shortened = blocksAlone(firstBlock, blockCount, r);
        if (shortened) hit |= 1u << r;
        return shortened;
      });
    }
    found |= hit;
    return hit;
  };
  OrientedPacketRays<FN> lanes(bvh, rays, live);
  walkOrientedPacket<FN>(bvh, lanes, rays, live, leaf, solo);
  return found;
}

}  // namespace obvh
