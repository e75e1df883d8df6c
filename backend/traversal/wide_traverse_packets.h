// Packet traversal of the wide BVHs (rtcIntersect4/8/16, rtcOccluded4/8/16 and streams): the rays
// of a packet share node loads, one stack and one near-to-far order, while every box decision and
// every triangle answer stays the single ray's. Included, like wide_traverse.h, only inside the
// per-ISA target regions (see wide_traversal_avx2.cpp).
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <type_traits>
#include <utility>

#include "intersect/watertight_lanes.h"
#include "memory/uninitialized_array.h"
#include "traversal/triangle_block_pairs.h"
#include "traversal/wide_traverse.h"

namespace obvh {

// body(std::integral_constant<int, count>{}) for a count in [1, kMax]: code made for a packet's
// number of lane groups as a constant, whose loops over the groups unroll and keep their values in
// registers.
template <int kMax, typename Body>
[[gnu::always_inline]] inline void withGroupCount(int count, Body&& body) {
  if constexpr (kMax > 1) {
    if (count != kMax) return withGroupCount<kMax - 1>(count, body);
  }
  body(std::integral_constant<int, kMax>{});
}

// A packet's rays as SIMD lanes (groups of FN::kWidth rays), for packets whose rays all share
// their direction signs and, along each axis, all move or all do not (an orthographic camera's
// rays move along one axis only): one child box is then tested against a whole group with the same
// per-ray operations as intersectWideNode's integer forms (near/far planes chosen by the sign bit,
// (org - plane) * -1/dir, the same max/min order, and for the axes the rays do not move along the
// same infinite distances), so every box decision stays the single ray's.
template <typename FN>
struct PacketLanes {
  static constexpr int kLanes = FN::kWidth;
  alignas(32) float org[3][kMaxPacketSize];
  alignas(32) float negInvDir[3][kMaxPacketSize];  // -1/dir, as WideRayFrame::negInv
  alignas(32) float tnear[kMaxPacketSize];
  alignas(32) float tfar[kMaxPacketSize];  // kept equal to the rays' tfar as hits shrink it
  int nearRow[3] = {}, farRow[3] = {};
  int zeroAxes = 0;  // bit axis: no ray of the packet moves along the axis (direction +-0)
  int groups = 0;
  bool usable = false;
  float originSpread = 0.f;  // the largest side of the box around the rays' origins

  // Usable when the rays of active share their direction's sign bits, have numbers for origins and
  // tnear (NaN rays go alone, where no box admits them), and along each axis either all move
  // (1/dir finite and non-zero) or all do not (a direction of +-0), along one axis at least: the
  // rays whose node tests take the integer forms (kBits, kBitsZeroAxes), with the same zero axes.
  // 1/dir, the signs and the zero-direction test are the single-ray frame's (WideRayFrame)
  // operations, done here for a lane group of rays at once (a division is exact, so 1/dir is the
  // same float either way): most packets never need a ray's full frame (only rays that go on alone
  // do). A lane group's origins, tnear and directions come out of one transposed load of its rays'
  // leading fields (FN::loadColumns); assembled lane by lane, eight values a row, the set-up was a
  // tenth of a coherent rtcIntersect8 packet's time (perf, bunny primary rays). rays must hold the
  // whole lane group of every active ray (kMaxPacketSize entries do); idle lanes may be
  // uninitialized, their values are replaced.
  PacketLanes(const Ray* rays, uint32_t active) {
    if (active == 0) return;
    // With a count known only at run time, a coherent rtcIntersect8 packet's set-up took 463
    // instructions on the bunny, 403 so (callgrind).
    withGroupCount<kMaxPacketSize / kLanes>((31 - __builtin_clz(active)) / kLanes + 1,
                                            [&](auto groups) { make<decltype(groups)::value>(rays, active); });
  }

 private:
  template <int kGroups>
  [[gnu::always_inline]] void make(const Ray* rays, uint32_t active) {
    static_assert(offsetof(Ray, org) == 0 && offsetof(Ray, tnear) == 3 * sizeof(float) &&
                      offsetof(Ray, dir) == 4 * sizeof(float) && sizeof(Ray) % sizeof(float) == 0,
                  "a ray's first eight floats are org, tnear, dir (and time)");
    static_assert(8 % kLanes == 0 && kMaxPacketSize % kLanes == 0);
    groups = kGroups;
    const FN zero = FN::broadcast(0.f), one = FN::broadcast(1.f);
    const FN largest = FN::broadcast(std::numeric_limits<float>::max()), lowest = zero - largest;
    const FN infinity = FN::broadcast(std::numeric_limits<float>::infinity());
    int negative[3] = {0, 0, 0};  // rays of active whose direction's sign bit is set, per axis
    int still[3] = {0, 0, 0};     // rays of active whose direction is +-0, per axis
    // The packet's bounds are thirteen minima over its rays: tnear, and per axis the origins, their
    // negations (for the maxima), 1/dir and its negation. Each lane group's are reduced together,
    // kLanes minima at once (FN::minOfEachRow), into `lows`, lane by lane over the groups. Reduced
    // one by one and combined in scalars, the set-up took 488 instructions a coherent
    // rtcIntersect8 packet on the bunny, 401 so (callgrind). Lanes without a ray hold +inf.
    constexpr int kBounds = 13, kRows = (kBounds + kLanes - 1) / kLanes;
    FN lows[kRows];
    for (FN& low : lows) low = infinity;
    for (int g = 0; g < kGroups; ++g) {
      const int base = g * kLanes;
      const int on = int((active >> base) & ((1u << kLanes) - 1));
      // Lanes without a ray enter nothing: nearT stays +inf, farT -inf.
      const FN tfarLanes = FN::fromLanes([&](int lane) { return rays[base + lane].tfar; });
      select(on, tfarLanes, zero - infinity).store(tfar + base);
      if (on == 0) {
        infinity.store(tnear + base);
        for (int axis = 0; axis < 3; ++axis) zero.store(org[axis] + base), zero.store(negInvDir[axis] + base);
        continue;
      }
      FN leading[8];  // org x, y, z, tnear, dir x, y, z, time of the group's rays
      for (int c = 0; c < 8; c += kLanes)
        FN::loadColumns(reinterpret_cast<const float*>(rays + base) + c, sizeof(Ray) / sizeof(float), leading + c);
      const FN tn = select(on, leading[3], infinity);
      tn.store(tnear + base);
      // The rays' box tests take the integer form of the single ray's (intersectWideNode), which
      // needs tnear +0 or positive and 1/dir finite and non-zero; other rays go alone.
      if ((bitsLessEqualMask(zero, tn) & lessEqualMask(tn, largest) & on) != on) return;
      FN bounds[kRows * kLanes];
      bounds[0] = tn;
      for (int k = kBounds; k < kRows * kLanes; ++k) bounds[k] = infinity;
      for (int axis = 0; axis < 3; ++axis) {
        const FN o = select(on, leading[axis], zero);
        const FN d = select(on, leading[4 + axis], infinity);
        if ((equalMask(o, o) & on) != on) return;
        const FN inv = one / d;  // idle lanes: 1 / inf = 0
        // Neither finite nor a zero direction's (NaN fails every comparison, a denormal direction
        // overflows): the single-ray frame's float form takes the ray.
        const int zeroLanes = equalMask(d, zero) & on;
        const int finite = lessEqualMask(inv, largest) & lessEqualMask(lowest, inv) & ~equalMask(inv, zero);
        if (((finite | zeroLanes) & on) != on) return;
        o.store(org[axis] + base);
        // A zero direction's -1/dir is -+inf, as in the single-ray frame.
        const FN negInv = zero - inv;
        negInv.store(negInvDir[axis] + base);
        negative[axis] |= (signMask(d) & on) << base;
        still[axis] |= zeroLanes << base;
        bounds[1 + axis] = select(on, o, infinity);
        bounds[4 + axis] = select(on, zero - o, infinity);
        bounds[7 + axis] = select(on, inv, infinity);
        bounds[10 + axis] = select(on, negInv, infinity);
      }
      for (int r = 0; r < kRows; ++r) lows[r] = min(lows[r], FN::minOfEachRow(bounds + r * kLanes));
    }
    alignas(32) float low[kRows * kLanes];
    for (int r = 0; r < kRows; ++r) lows[r].store(low + r * kLanes);
    tnearLow = low[0];
    for (int axis = 0; axis < 3; ++axis) {
      // Mixed signs: the rays' boxes would be tested ray by ray along the union of their paths.
      if (negative[axis] != 0 && uint32_t(negative[axis]) != active) return;
      // Some rays move along the axis and some do not: their node tests take different forms.
      if (still[axis] != 0 && uint32_t(still[axis]) != active) return;
      nearRow[axis] = entryRow(axis, negative[axis] != 0);
      farRow[axis] = exitRow(axis, negative[axis] != 0);
      // The packet's bounds per axis: origin and 1/dir ranges (1/dir has one sign per axis here).
      const float orgLow = low[1 + axis], orgHigh = 0.f - low[4 + axis];
      const float invLow = low[7 + axis], invHigh = 0.f - low[10 + axis];
      originSpread = std::max(originSpread, orgHigh - orgLow);
      if (still[axis] != 0) {
        zeroAxes |= 1 << axis;
        orgBounds[axis][0] = FN::broadcast(orgLow);
        orgBounds[axis][1] = FN::broadcast(orgHigh);
      }
      const bool positive = invLow > 0.f;
      nearBoundOrg[axis] = FN::broadcast(positive ? orgHigh : orgLow);
      farBoundOrg[axis] = FN::broadcast(positive ? orgLow : orgHigh);
      invNear[axis] = FN::broadcast(positive ? invLow : invHigh);
      invFar[axis] = FN::broadcast(positive ? invHigh : invLow);
    }
    // Rays that move along no axis: the single-ray frame's float form.
    if (zeroAxes == 7) return;
    refreshTfar<kGroups>(rays, 0u);
    usable = true;
  }

 public:
  // The children that some ray of the packet may enter, from one test of all of them against the
  // packet's bounds. Every step is monotone in its operands (rounded subtraction and
  // multiplication, min, max), so the bounds are bounds of the values each ray computes, not only
  // of exact ones: nearLow <= every ray's entry distance and farHigh >= every ray's exit distance,
  // and a child with nearLow > farHigh is entered by none. One product a plane: a distance is at
  // its lowest with the 1/dir of the smallest magnitude (invNear) and at its highest with that of
  // the largest (invFar) wherever it is positive, and negative distances need no tight bound (an
  // entry below the smallest tnear, >= 0, decides nothing; an exit below zero admits no ray either
  // way). With both products' minimum and maximum, the test took about 11 instructions more a node
  // (callgrind, bunny coherent rtcIntersect8). An unused child (NaN bounds) gets a NaN
  // nearLow and fails, as in the per-ray test. nearBound gets nearLow.
  // kZeroAxes: zeroAxes is not 0. Along a zero axis a ray enters exactly the slabs that hold its
  // origin (the float form's test, which the integer form's infinite distances reproduce): no ray
  // enters a slab that the packet's range of origins misses.
  // planes gets the node's near planes (x, y, z) and far planes, in the rays' order.
  template <bool kZeroAxes, int N>
  int mayEnter(const WideNode<N>& node, float nearBound[N], float planes[6][N]) const {
    static_assert(N == kLanes, "one lane per child");
    FN nearLow = FN::broadcast(tnearLow);
    FN farHigh = FN::broadcast(std::numeric_limits<float>::infinity());
    int inside = (1 << N) - 1;
    for (int axis = 0; axis < 3; ++axis) {
      const FN nearPlane = FN::load(node.bounds[nearRow[axis]]), farPlane = FN::load(node.bounds[farRow[axis]]);
      nearPlane.store(planes[axis]);
      farPlane.store(planes[3 + axis]);
      if (kZeroAxes && ((zeroAxes >> axis) & 1)) {
        inside &= lessEqualMask(FN::load(node.bounds[axis * 2]), orgBounds[axis][1]) &
                  lessEqualMask(orgBounds[axis][0], FN::load(node.bounds[axis * 2 + 1]));
        continue;
      }
      nearLow = max(nearLow, (nearPlane - nearBoundOrg[axis]) * invNear[axis]);
      farHigh = min(farHigh, (farPlane - farBoundOrg[axis]) * invFar[axis]);
    }
    farHigh = min(bitsPlus(farHigh, kConservativeFarUlps), FN::broadcast(tfarHigh));
    nearLow.store(nearBound);
    return lessEqualMask(nearLow, farHigh) & inside;
  }

  // Tests every child of node against the rays in `rays`: childRays[c] gets the rays entering
  // child c, childEntry[c] (aligned for FN) a lower bound of their entry distances, the packet
  // bounds' (mayEnter); returns the mask of entered children. A bound is all the walk needs: it
  // orders the children and, at a pop, drops the rays whose segment ends before it, which a
  // smaller bound does less often but never wrongly. The rays' own smallest entry, a reduction per
  // entered child and lane group, took about 5% of a coherent packet's instructions.
  // kZeroAxes: zeroAxes is not 0 (intersectWideNode's form kBitsZeroAxes).
  // kGroups: the packet's number of lane groups (groups), as a constant.
  template <bool kZeroAxes, int kGroups, int N>
  int intersectNode(const WideNode<N>& node, uint32_t rays, uint32_t childRays[N], float childEntry[N]) const {
    int entered = 0;
    // Each child's planes are broadcast from this copy in the rays' order: from the node's rows,
    // each broadcast took an address computed from the rays' row choice.
    alignas(32) float planes[6][N];
    const int candidateChildren = mayEnter<kZeroAxes>(node, childEntry, planes);
    if (candidateChildren == 0) return 0;
    for (int g = 0; g < kGroups; ++g) {
      const uint32_t groupRays = (rays >> (g * kLanes)) & ((1u << kLanes) - 1);
      if (groupRays == 0) continue;
      const int base = g * kLanes;
      const FN o[3] = {FN::load(org[0] + base), FN::load(org[1] + base), FN::load(org[2] + base)};
      const FN negInv[3] = {FN::load(negInvDir[0] + base), FN::load(negInvDir[1] + base), FN::load(negInvDir[2] + base)};
      const FN tnearLanes = FN::load(tnear + base), tfarLanes = FN::load(tfar + base);
      for (int candidates = candidateChildren; candidates; candidates &= candidates - 1) {
        const int c = __builtin_ctz(unsigned(candidates));
        FN entryT[3], exitT[3];
        for (int axis = 0; axis < 3; ++axis) {
          entryT[axis] = (o[axis] - FN::broadcast(planes[axis][c])) * negInv[axis];
          exitT[axis] = (o[axis] - FN::broadcast(planes[3 + axis][c])) * negInv[axis];
          // As intersectWideNode's form kBitsZeroAxes: a NaN exit (origin on a plane) becomes +inf.
          if (kZeroAxes) exitT[axis] = min(exitT[axis], FN::broadcast(std::numeric_limits<float>::infinity()));
        }
        const FN nearT = maxOfBits(maxOfBits(entryT[0], entryT[1]), maxOfBits(tnearLanes, entryT[2]));
        const FN farT =
            minOfBits(bitsPlus(minOfBits(minOfBits(exitT[0], exitT[1]), exitT[2]), kConservativeFarUlps), tfarLanes);
        const uint32_t in = uint32_t(bitsLessEqualMask(nearT, farT)) & groupRays;
        if (in == 0) continue;
        childRays[c] |= in << base;
        entered |= 1 << c;
      }
    }
    return entered;
  }

  // The rays among `rays` whose segment ends before t (their tfar as last refreshed); kGroups as
  // intersectNode's.
  template <int kGroups>
  uint32_t raysEndingBefore(float t, uint32_t rays) const {
    uint32_t ending = 0;
    const FN at = FN::broadcast(t);
    for (int g = 0; g < kGroups; ++g)
      if ((rays >> (g * kLanes)) & ((1u << kLanes) - 1))
        ending |= uint32_t(lessMask(FN::load(tfar + g * kLanes), at)) << (g * kLanes);
    return ending & rays;
  }

  // The smallest tnear of the packet's rays (made with the lanes, of a usable packet).
  float smallestTnear() const { return tnearLow; }

  // Takes the tfar of the rays in `changed` from rays (rays must hold the whole lane group of each,
  // as for the constructor), and the largest tfar of all, a NaN counting as none (as std::max
  // skipped it): a vector maximum over the lane groups and one reduction, where a scalar pass over
  // every lane took about 25 instructions after every leaf a packet visits. A lane group's tfar is
  // written as one vector store: written lane by lane, the vector loads that read them next (here
  // and in the node tests) waited for the scalar stores.
  // kGroups as intersectNode's.
  template <int kGroups>
  void refreshTfar(const Ray* rays, uint32_t changed) {
    const FN none = FN::broadcast(-std::numeric_limits<float>::infinity());
    FN high = none;
    for (int g = 0; g < kGroups; ++g) {
      const int base = g * kLanes;
      FN lanes = FN::load(tfar + base);
      const int changedLanes = int((changed >> base) & ((1u << kLanes) - 1));
      if (changedLanes != 0) {
        lanes = select(changedLanes, FN::fromLanes([&](int lane) { return rays[base + lane].tfar; }), lanes);
        lanes.store(tfar + base);
      }
      high = max(high, replaceNaN(lanes, none));
    }
    const FN zero = FN::broadcast(0.f);
    tfarHigh = 0.f - minOfLanes(zero - high, (1 << kLanes) - 1);
  }

 private:
  FN nearBoundOrg[3], farBoundOrg[3];  // the origin bound that bounds each plane's distance
  FN orgBounds[3][2];                  // lowest and highest origin, along the zero axes
  // Per axis, the 1/dir of the smallest magnitude and that of the largest (mayEnter).
  FN invNear[3], invFar[3];
  float tnearLow = 0.f, tfarHigh = 0.f;
};

// Packet traversal: every box decision is the single ray's (the rays as SIMD lanes per child box,
// PacketLanes), while the packet shares the node loads, one stack and one near-to-far order (by the
// smallest entry distance among the rays entering a child). leafVisitor(firstBlock, blockCount,
// rays) tests the rays against a leaf and soloVisitor(node, rays) traces each of them through that
// subtree alone (single-ray traversal, which orders and culls per ray). Both return, for any-hit
// walks, the rays finished, which leave the packet, and for closest-hit walks (kNearToFar) the rays
// whose segment they shortened (a hit), whose tfar the packet's lanes then take: refreshed only for
// those, rather than for every ray the visit tested (and not at all after a visit without a hit),
// the bunny's coherent rtcIntersect8 packets took 21 instructions fewer a packet (callgrind) and
// traced 1.005-1.014x as fast (paired ladder, both load orders). The rays go alone for the whole
// packet when they do not share their direction signs, and wherever no more rays than the packet's
// solo threshold enter an interior node, where sharing the node loads no longer pays. Packets whose
// origins lie close together (camera rays, shadow rays from neighbouring hits) share nodes down to
// two rays: going alone at two or four traced 2-7% slower on them since the packet's node test and
// pops went SIMD over the rays. Packets whose origins spread over more than an eighth of the scene
// share little below the top levels: they go alone at four rays (at one, incoherent shadow packets
// traced 8% slower).
constexpr int kPacketSoloRaysClose = 1;
constexpr int kPacketSoloRaysSpread = 4;
constexpr float kPacketSpreadFraction = 0.125f;

// The walk of traverseWidePacket once the packet's lanes are made (kZeroAxes: lanes.zeroAxes is not
// 0; kGroups: lanes.groups).
template <typename FN, bool kNearToFar, bool kZeroAxes, int kGroups, typename LeafVisitor, typename SoloVisitor>
void walkWidePacket(const TriangleWideView<FN::kWidth>& bvh, PacketLanes<FN>& lanes, const Ray* rays,
                    uint32_t active, LeafVisitor&& leafVisitor, SoloVisitor&& soloVisitor) {
  constexpr int N = FN::kWidth;
  using Node = WideNode<N>;
  const int soloRays =
      lanes.originSpread > bvh.extent * kPacketSpreadFraction ? kPacketSoloRaysSpread : kPacketSoloRaysClose;
  struct Entry {
    uint32_t child;
    uint32_t rays;
    float t;  // smallest entry distance of these rays
  };
  Entry stack[(N - 1) * 128];
  int top = 0;
  const float tnearMin = lanes.smallestTnear();
  // Drops the rays that finished, and those whose segment ends before every ray's entry (only
  // closest-hit rays' segments shrink).
  const auto raysStillIn = [&](const Entry& e) {
    const uint32_t in = e.rays & active;
    return kNearToFar ? in & ~lanes.template raysEndingBefore<kGroups>(e.t, in) : in;
  };
  // The root starts in registers, not on the stack (see traverseWide).
  uint32_t current = bvh.root, currentRays = raysStillIn({bvh.root, active, tnearMin});
  for (;;) {
    while (currentRays) {
      // Any-hit rays keep their tfar (those that finish leave the packet).
      const auto take = [&](uint32_t reported) {
        if (kNearToFar) {
          if (reported) lanes.template refreshTfar<kGroups>(rays, reported);
        } else {
          active &= ~reported;
        }
      };
      if (Node::isLeaf(current)) {
        take(leafVisitor(Node::leafFirstBlock(current), Node::leafBlockCount(current), currentRays));
        if (active == 0) return;
        break;
      }
      if (__builtin_popcount(currentRays) <= soloRays) {
        take(soloVisitor(current, currentRays));
        if (active == 0) return;
        break;
      }
      const Node& node = bvh.nodes[current];
      uint32_t childRays[N] = {};
      alignas(32) float childEntry[N];
      int entered = lanes.template intersectNode<kZeroAxes, kGroups>(node, currentRays, childRays, childEntry);
      if (entered == 0) break;
      // One or two children entered (the bunny's camera packets enter 1.47 a node visit, the
      // dragon's 1.79, on average): the nearer is taken next and the other pushed, without the
      // general sort's entry records. Through the sort, every packet row traced 1.5-5% slower
      // (paired probe, bunny, motorBike and dragon).
      const int others = entered & (entered - 1);
      if ((others & (others - 1)) == 0) {
        int nearChild = __builtin_ctz(unsigned(entered));
        if (others != 0) {
          int farChild = __builtin_ctz(unsigned(others));
          if (kNearToFar && childEntry[farChild] < childEntry[nearChild]) std::swap(nearChild, farChild);
          prefetchChild<FN>(bvh, node.child[farChild]);
          stack[top++] = Entry{node.child[farChild], childRays[farChild], childEntry[farChild]};
        }
        current = node.child[nearChild];
        prefetchChild<FN>(bvh, current);
        currentRays = childRays[nearChild] & active;
        continue;
      }
      Entry hits[N];
      int n = 0;
      while (entered) {
        const int c = __builtin_ctz(unsigned(entered));
        entered &= entered - 1;
        Entry h{node.child[c], childRays[c], childEntry[c]};
        prefetchChild<FN>(bvh, h.child);
        int k = n++;
        while (kNearToFar && k > 0 && hits[k - 1].t > h.t) {
          hits[k] = hits[k - 1];
          --k;
        }
        hits[k] = h;
      }
      for (int k = n - 1; k >= 1; --k) stack[top++] = hits[k];
      current = hits[0].child;
      currentRays = hits[0].rays & active;
    }
    if (top == 0) return;
    const Entry e = stack[--top];
    current = e.child;
    currentRays = raysStillIn(e);
  }
}

template <typename FN, bool kNearToFar, typename LeafVisitor, typename SoloVisitor>
void traverseWidePacket(const TriangleWideView<FN::kWidth>& bvh, const Ray* rays, uint32_t active,
                        LeafVisitor&& leafVisitor, SoloVisitor&& soloVisitor) {
  using Node = WideNode<FN::kWidth>;
  if (bvh.empty() || active == 0) return;
  if (Node::isLeaf(bvh.root)) {
    leafVisitor(Node::leafFirstBlock(bvh.root), Node::leafBlockCount(bvh.root), active);
    return;
  }
  PacketLanes<FN> lanes(rays, active);
  if (!lanes.usable) {
    // Rays of differing direction signs gain nothing from travelling together (every node's boxes
    // would be tested ray by ray, along the union of their paths), nor do rays whose node tests
    // take different forms: each goes alone.
    soloVisitor(bvh.root, active);
    return;
  }
  // The walk for the lanes' number of groups as a constant: the loops over the groups in every node
  // test, pop and refresh unroll (bunny coherent rtcIntersect8: 414 -> 388 instructions a ray,
  // callgrind; 1.01-1.03x as fast, rtcOccluded8 unchanged within 1%).
  withGroupCount<kMaxPacketSize / FN::kWidth>(lanes.groups, [&](auto groups) {
    constexpr int kGroups = decltype(groups)::value;
    if (lanes.zeroAxes != 0)
      walkWidePacket<FN, kNearToFar, true, kGroups>(bvh, lanes, rays, active, leafVisitor, soloVisitor);
    else
      walkWidePacket<FN, kNearToFar, false, kGroups>(bvh, lanes, rays, active, leafVisitor, soloVisitor);
  });
}

// The per-ray constants of a packet's active lanes. Rays with an empty segment (tnear > tfar, as
// the unused lanes of a shadow packet often are) have already been dropped where the packet was
// gathered (QueryDispatch's gatherLiveLanes; one that got here would enter no box, only cost
// time): checking them again, ray by ray, was about 100 instructions a packet of eight. The
// triangle-test frames of a lane group's live rays are made together, as SIMD lanes
// (watertightFramesOfLanes), when a leaf first needs one of them: a packet that reaches no leaf
// makes none. A ray that goes on alone makes its box-test frame where it does, as a local the
// compiler keeps in registers: made for every ray up front and kept in an array, packets traced
// 2-6% slower (paired probe).
template <typename FN>
struct PacketFrames {
  uint32_t live = 0;

  explicit PacketFrames(uint32_t active) : live(active) {}

  // Makes the triangle-test frames of the rays of `wanted` (live rays) that have none yet,
  // together with those of their lane groups' other live rays. rays holds the whole lane group of
  // every live ray, as for PacketLanes.
  [[gnu::always_inline]] void prepare(const Ray* rays, uint32_t wanted) {
    constexpr int kLanes = FN::kWidth;
    constexpr uint32_t kGroup = (1u << kLanes) - 1;
    for (uint32_t missing = wanted & ~prepared_; missing;) {
      const int base = __builtin_ctz(missing) & ~(kLanes - 1);
      const uint32_t group = ((live | missing) >> base) & kGroup;
      watertightFramesOfLanes<FN>(rays + base, watertight_.data() + base, group);
      prepared_ |= group << base;
      missing &= ~(kGroup << base);
    }
  }
  // Ray r's triangle-test frame, made if it is not yet.
  [[gnu::always_inline]] const WatertightRay& triangleFrame(const Ray* rays, int r) {
    prepare(rays, 1u << r);
    return watertight_[r];
  }
  // The frames of rays already prepared, for the leaves' tests of several rays
  // (triangle_block_pairs.h).
  auto preparedFrames() const {
    return [this](int r) -> const WatertightRay& { return watertight_[r]; };
  }

 private:
  UninitializedArray<WatertightRay, kMaxPacketSize> watertight_;
  uint32_t prepared_ = 0;
};

// A packet's rays that reach a leaf are tested against its blocks' four triangles at a time, two
// rays in one eight-lane pass where they share the watertight frame's axis order
// (triangle_block_pairs.h; paired probe against one by one, bunny / motorBike / dragon: coherent
// rtcIntersect8 1.02 / 1.02 / 1.02, rtcOccluded8 1.05 / 1.03 / 1.00, orthographic 1.03 / 1.03 /
// 1.02). PairLanes is that eight-lane type: FN for eight-wide nodes; with four-wide ones each ray
// goes alone. Until 2026-11-30 leaves that three quarters of a lane group reached tested the rays
// as the lanes of one triangle's test (the packet leaf, triangle_packet_leaf.h): against the pairs
// with that leaf dropped, bunny / motorBike / dragon traced 1.03 / 1.00 / 1.00 as fast (coherent
// rtcIntersect8), 1.00 / 1.02 / 1.01 (rtcOccluded8) and 1.03 / 1.05 / 1.00 (orthographic), and
// the stacks small-1.5k 1.06-1.07, diagonal-42k 1.01-1.04, axis-516k 1.01-1.02, mixed-654k
// 1.01-1.03 (paired probe). The lanes shared each triangle's loads, but every candidate they found
// took the scalar double-precision second half, where a ray's own block test takes it for four
// triangles at once (simd/double_lanes.h).
template <typename FN>
using PairLanes = std::conditional_t<FN::kWidth == 8, FN, void>;

template <typename FN, typename F4>
uint32_t intersectClosestWidePacketImpl(const TriangleWideView<FN::kWidth>& bvh, Ray* rays, Hit* hits,
                                        uint32_t active, const QueryState& state) {
  PacketFrames<FN> f(active);
  uint32_t found = 0;
  // Whether ray r, traced alone from start, found a hit.
  const auto closestAlone = [&](uint32_t start, int r) {
    bool hit = false;
    const WideRayFrame<FN> frame(rays[r]);
    traverseWideFrom<FN, true>(bvh, start, frame, rays[r], [&](uint32_t firstBlock, uint32_t blockCount) {
      const bool shortened = intersectBlocksClosest<F4, simd::DoubleLanes<FN>>(
          bvh.set, bvh.blocks, firstBlock, blockCount, f.triangleFrame(rays, r), rays[r], hits[r], state);
      hit |= shortened;
      return shortened;
    });
    return hit;
  };
  const auto leaf = [&](uint32_t firstBlock, uint32_t blockCount, uint32_t mask) {
    // Rays declared coherent (camera rays) start away from surfaces: their blocks leave out the
    // check for candidates behind the origin, as the single-ray kernels for such rays do (bunny
    // coherent rtcIntersect8: 378 -> 374 instructions a ray, callgrind). One instantiation for
    // each form: a generic lambda instantiated for both took 5 instructions a ray more.
    f.prepare(rays, mask);
    const uint32_t hit =
        state.coherent ? intersectBlocksClosestOfRays<F4, PairLanes<FN>, simd::DoubleLanes<FN>, false>(
                             bvh.set, bvh.blocks, firstBlock, blockCount, f.preparedFrames(), rays, hits, mask, state)
                       : intersectBlocksClosestOfRays<F4, PairLanes<FN>, simd::DoubleLanes<FN>, true>(
                             bvh.set, bvh.blocks, firstBlock, blockCount, f.preparedFrames(), rays, hits, mask, state);
    found |= hit;
    return hit;
  };
  const auto solo = [&](uint32_t node, uint32_t mask) {
    uint32_t hit = 0;
    for (; mask; mask &= mask - 1)
      if (closestAlone(node, __builtin_ctz(mask))) hit |= 1u << __builtin_ctz(mask);
    found |= hit;
    return hit;
  };
  traverseWidePacket<FN, true>(bvh, rays, f.live, leaf, solo);
  return found;
}

template <typename FN, typename F4>
uint32_t intersectAnyWidePacketImpl(const TriangleWideView<FN::kWidth>& bvh, const Ray* rays, uint32_t active,
                                    const QueryState& state) {
  PacketFrames<FN> f(active);
  uint32_t occluded = 0;
  const auto anyAlone = [&](uint32_t start, int r) {
    bool found = false;
    const WideRayFrame<FN> frame(rays[r]);
    traverseWideFrom<FN, false>(bvh, start, frame, rays[r], [&](uint32_t firstBlock, uint32_t blockCount) {
      found = intersectBlocksAny<F4, simd::DoubleLanes<FN>>(bvh.set, bvh.blocks, firstBlock, blockCount, f.triangleFrame(rays, r), rays[r],
                                     state);
      return found;
    });
    return found;
  };
  const auto leaf = [&](uint32_t firstBlock, uint32_t blockCount, uint32_t mask) {
    f.prepare(rays, mask);
    const uint32_t finished = intersectBlocksAnyOfRays<F4, PairLanes<FN>, simd::DoubleLanes<FN>>(
        bvh.set, bvh.blocks, firstBlock, blockCount, f.preparedFrames(), rays, mask, state);
    occluded |= finished;
    return finished;
  };
  const auto solo = [&](uint32_t node, uint32_t mask) {
    uint32_t finished = 0;
    for (; mask; mask &= mask - 1)
      if (anyAlone(node, __builtin_ctz(mask))) finished |= 1u << __builtin_ctz(mask);
    occluded |= finished;
    return finished;
  };
  traverseWidePacket<FN, false>(bvh, rays, f.live, leaf, solo);
  return occluded;
}

}  // namespace obvh
