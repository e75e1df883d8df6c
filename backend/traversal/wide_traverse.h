// Single-ray traversal of the wide BVHs, templated on the node vector type (width 4 or 8) and the
// four-lane type of the triangle-block test (packets: wide_traverse_packets.h). Included only by
// the per-ISA translation units, inside their target region (see wide_traversal_avx2.cpp): every
// template here is instantiated with that file's own vector type, so no other file can end up
// with its copy.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <limits>

#include "simd/double_lanes.h"
#include "traversal/box_test.h"
#include "traversal/triangle_block_leaf.h"
#include "traversal/wide_traversal.h"
#include "traversal/wide_walk.h"

namespace obvh {

// Rows of WideNode::bounds holding an axis' entry and exit planes for a ray whose direction along
// that axis is negative or not: with a positive direction the lower plane is entered first.
constexpr int entryRow(int axis, bool negative) { return axis * 2 + int(negative); }
constexpr int exitRow(int axis, bool negative) { return axis * 2 + 1 - int(negative); }

// The byte offsets of each axis' entry row (entryRow) for every combination of direction signs
// (bit axis set: negative), for nodes N lanes wide.
template <int N>
struct NearRowBytes {
  uint32_t bytes[4];  // x, y, z; the fourth pads an entry to 16 bytes
};
template <int N>
constexpr NearRowBytes<N> nearRowBytesFor(int negative) {
  NearRowBytes<N> r{};
  for (int axis = 0; axis < 3; ++axis)
    r.bytes[axis] = uint32_t(entryRow(axis, (negative >> axis) & 1)) * uint32_t(N * sizeof(float));
  return r;
}
template <int N>
inline constexpr NearRowBytes<N> kNearRowBytes[8] = {nearRowBytesFor<N>(0), nearRowBytesFor<N>(1), nearRowBytesFor<N>(2),
                                                     nearRowBytesFor<N>(3), nearRowBytesFor<N>(4), nearRowBytesFor<N>(5),
                                                     nearRowBytesFor<N>(6), nearRowBytesFor<N>(7)};

// The float whose bits are -(kConservativeFarUlps + 1).
inline float nearAllowanceValue() {
  const int32_t bits = -(kConservativeFarUlps + 1);
  float value;
  std::memcpy(&value, &bits, sizeof value);
  return value;
}

// tnear +0 or positive, and finite: the integer forms' entries are then non-negative floats.
inline bool tnearAllowsIntegerForm(float tnear) {
  return !std::signbit(tnear) && tnear <= std::numeric_limits<float>::max();
}

// What the frame and the root-box test need of a ray's direction, worked out once a ray (each
// made the division and its checks itself). Lanes x, y, z of F4; the fourth is 1, not the ray's
// time that follows dir (see Ray): 1/0 would raise the division-by-zero flag for every ray, which
// an application trapping that exception would take for its own error.
template <typename F4>
struct RayDirection {
  F4 dir, inv;  // inv = 1/dir (a division is exact, so the same float however computed)
  // Bit masks over the axes: 1/dir finite and non-zero (denormal directions overflow 1/dir, NaN
  // fails the compares); the direction's sign bit set (so that a direction of -0 takes the planes
  // of a negative one: the integer forms' zero axes rely on it).
  int usable, negative;
  // usable along every axis, and tnear +0 or positive: the ray's node tests take the integer form
  // without zero axes (NodeTestForm::kBits), the form of nearly every ray.
  bool integerForm;

  [[gnu::always_inline]] explicit RayDirection(const Ray& ray) {
    static_assert(offsetof(Ray, time) == offsetof(Ray, dir) + 3 * sizeof(float));
    dir = F4::loadThree(&ray.dir.x, 1.f);
    inv = F4::broadcast(1.f) / dir;
    const F4 zero = F4::broadcast(0.f), largest = F4::broadcast(std::numeric_limits<float>::max());
    usable = lessEqualMask(zero - largest, inv) & lessEqualMask(inv, largest) & ~equalMask(inv, zero) & 7;
    negative = signMask(dir) & 7;
    integerForm = usable == 7 && tnearAllowsIntegerForm(ray.tnear);
  }
};

template <typename FN>
struct WideRayFrame {
  // -1/dir: the slab distance (plane - org) * inv is computed as (org - plane) * negInv, the same
  // float (negation is exact), so that the node's plane is the memory operand of the subtraction.
  FN org[3], negInv[3];
  FN tnear;
  // -(kConservativeFarUlps + 1) in every lane's bits (see intersectWideNode): kept with the frame, so
  // that the node test adds it from memory rather than making it anew.
  FN nearAllowance;
  // The rows of WideNode::bounds holding each axis' entry plane (entryRow) as byte offsets; the
  // exit plane's is nearByte ^ (bytes of a row). Three offsets, where six row indices were
  // reloaded from the stack at every node.
  uint32_t nearByte[3];
  int zeroAxes;               // bit axis: the ray does not move along the axis (direction +-0)
  // tnear +0 or positive, and along every axis 1/dir finite and non-zero or the direction exactly
  // zero: the node test may then reduce the slab distances as integers (see intersectWideNode);
  // other rays (denormal or infinite directions, negative or NaN tnear) take the float form.
  bool bitOrdered;

  WideRayFrame() = default;
  // Always inlined: as a call (GCC kept it out of line) the frame went through memory. The three
  // axes' reciprocals and their checks are one four-lane operation each (RayDirection): axis by
  // axis, the set-up took 148 instructions a ray, then 109 (callgrind, bunny primary rays, AVX2
  // kernel).
  [[gnu::always_inline]] WideRayFrame(const Ray& ray, const RayDirection<typename FN::Lanes4>& d) {
    broadcastRay(ray, d);
    zeroAxes = equalMask(d.dir, FN::Lanes4::broadcast(0.f)) & 7;
    // A ray that moves along no axis has no slab to reject an unused lane (see intersectWideNode).
    bitOrdered = tnearAllowsIntegerForm(ray.tnear) && zeroAxes != 7 && (zeroAxes | d.usable) == 7;
  }
  [[gnu::always_inline]] explicit WideRayFrame(const Ray& ray) : WideRayFrame(ray, RayDirection<typename FN::Lanes4>(ray)) {}

  // The frame of a ray whose direction analysis says integerForm: the checks' answers are known.
  [[gnu::always_inline]] static WideRayFrame ofIntegerForm(const Ray& ray, const RayDirection<typename FN::Lanes4>& d) {
    WideRayFrame frame;
    frame.broadcastRay(ray, d);
    frame.zeroAxes = 0;
    frame.bitOrdered = true;
    return frame;
  }

 private:
  [[gnu::always_inline]] void broadcastRay(const Ray& ray, const RayDirection<typename FN::Lanes4>& d) {
    alignas(16) float invLanes[4];
    d.inv.store(invLanes);
    tnear = FN::broadcast(ray.tnear);
    float allowance = nearAllowanceValue();
    // Opaque to the compiler, which otherwise made the constant anew at every node (three
    // instructions) rather than read it from the frame.
    asm("" : "+x"(allowance));
    nearAllowance = FN::broadcast(allowance);
    for (int axis = 0; axis < 3; ++axis) {
      org[axis] = FN::broadcast(ray.org[axis]);
      // A zero direction's 1/dir is inf (the integer form's infinite slab distances; the float
      // form takes the origin-inside-slab test instead).
      negInv[axis] = FN::broadcast(-invLanes[axis]);
    }
    // The slab distances of the planes entered and left first are the values the min/max form
    // picks, without computing both. Read from a table by the three sign bits rather than computed
    // axis by axis (with the triangle frame's uninitialized storage, triangle_leaf.h: 237.5 -> 226.2
    // instructions a bunny camera ray that misses, callgrind).
    const NearRowBytes<FN::kWidth>& rows = kNearRowBytes<FN::kWidth>[d.negative];
    for (int axis = 0; axis < 3; ++axis) nearByte[axis] = rows.bytes[axis];
  }
};

// Which form of the node test a ray takes, decided once a ray (each a separate walk), not at every
// node.
enum class NodeTestForm {
  kBits,           // the frame is bitOrdered and the ray moves along every axis
  kBitsZeroAxes,   // bitOrdered, with axes along which the ray does not move (orthographic views)
  kFloat,          // the rest
};

template <typename FN>
NodeTestForm nodeTestFormOf(const WideRayFrame<FN>& frame) {
  if (!frame.bitOrdered) return NodeTestForm::kFloat;
  // With bitOrdered, an axis whose 1/dir is not finite is one the ray does not move along.
  return frame.zeroAxes != 0 ? NodeTestForm::kBitsZeroAxes : NodeTestForm::kBits;
}

// tfar as the integer forms take it: kConservativeFarUlps taken off its bits, or the smallest
// integer (a NaN's bits) for a negative tfar, which no entry distance lies below.
inline int32_t exitLimitBits(float tfar) {
  int32_t bits;
  std::memcpy(&bits, &tfar, sizeof bits);
  return bits < 0 ? std::numeric_limits<int32_t>::min() : bits - kConservativeFarUlps;
}
// tfar as intersectWideNode's form kForm takes it, broadcast (exitLimitBits for the integer forms).
template <NodeTestForm kForm, typename FN>
FN exitLimitLanes(float tfar) {
  if constexpr (kForm == NodeTestForm::kFloat) {
    return FN::broadcast(tfar);
  } else {
    const int32_t bits = exitLimitBits(tfar);
    float lowered;
    std::memcpy(&lowered, &bits, sizeof lowered);
    return FN::broadcast(lowered);
  }
}

// True when the ray enters none of the root node's children because its segment misses the box
// around them (TriangleWideView::rootLower, rootUpper): such rays, half of a camera's over a single
// object, then skip the node test's set-up (the eight-wide frame) and the root node's test. Only for
// rays whose node tests take the integer form (NodeTestForm::kBits: RayDirection::integerForm,
// which the caller checks). The box's planes lie outside its children's, and each step (rounded
// subtraction and multiplication, max, min) is monotone, so the box's entry is no later and its
// exit no earlier than any child's, with the same allowance of ulps: no ray that a child admits is
// turned away.
template <typename FN>
[[gnu::always_inline]] inline bool missesRootBox(const TriangleWideView<FN::kWidth>& bvh, const Ray& ray,
                                                 const RayDirection<typename FN::Lanes4>& d) {
  using F4 = typename FN::Lanes4;
  const F4 zero = F4::broadcast(0.f);
  const F4 org = F4::loadThree(&ray.org.x, 0.f), negInv = zero - d.inv;
  const F4 lower = F4::load(bvh.rootLower), upper = F4::load(bvh.rootUpper);
  // The planes entered and left first as the smaller and larger distance: the same floats as the
  // node test's planes chosen by the direction's sign.
  const F4 toLower = (org - lower) * negInv, toUpper = (org - upper) * negInv;
  // No check for NaN distances (an origin not a number; 8 instructions a ray): whatever this test
  // answers for such a ray, the walk's integer node test enters no child for it either, so the
  // ray hits nothing. Its slab distances along that axis are NaN for every child; a NaN whose sign
  // bit is clear is, on the bits, above every entry (it becomes the child's entry), and one whose
  // sign bit is set is below every exit (it becomes the child's exit): the child fails the compare.
  const F4 entry = min(toLower, toUpper), exit = max(toLower, toUpper);
  alignas(16) float entries[4], exits[4];
  entry.store(entries);
  exit.store(exits);
  const float nearT = std::max(std::max(ray.tnear, entries[0]), std::max(entries[1], entries[2]));
  const float farT = std::min(std::min(exits[0], exits[1]), exits[2]);
  // intersectWideNode's integer test: min(exit, tfar - k) > near - (k + 1), on the bits.
  int32_t nearBits, farBits;
  std::memcpy(&nearBits, &nearT, sizeof nearBits);
  std::memcpy(&farBits, &farT, sizeof farBits);
  return !(std::min(farBits, exitLimitBits(ray.tfar)) > nearBits - (kConservativeFarUlps + 1));
}

// Tests the node's child boxes; returns a bit mask of the entered ones and their entry distances.
// kForm: see NodeTestForm. In the integer forms every slab distance is a float whose bit pattern
// orders as the float does when it is non-negative, and below every non-negative one when it is
// negative, so that the maximum with tnear (>= +0) and the minimum of the exits come out of
// integer max/min, the exit's allowance of ulps is an integer add on the bits (taken off tfar and
// the entry, see below), and the compare is an integer one: one cycle each on the chain from one
// node's load to the next, where the float forms take four (an unused lane's NaN bounds give NaN
// distances of either sign: a positive one ends as the largest entry, a negative one as the
// smallest exit, and the lane fails the compare either way). In the float form a ray that does not
// move along an axis is inside that slab exactly when its origin lies within [lower, upper]
// (inclusive), as in the scalar box test; the integer form with zero axes gets the same slabs from
// infinite distances (below). The float form's conservative far scaling is Ize's.
// tfarLanes: tfar broadcast, for the integer forms lowered first (exitLimitLanes).
template <NodeTestForm kForm, typename FN, int N>
[[gnu::always_inline]] inline int intersectWideNode(const WideNode<N>& node, const WideRayFrame<FN>& r,
                                                    const FN& tfarLanes, float entry[N]) {
  if constexpr (kForm != NodeTestForm::kFloat) {
    static_assert(sizeof(node.bounds[0]) == N * sizeof(float) && (N & (N - 1)) == 0);
    const char* rows = reinterpret_cast<const char*>(node.bounds);
    FN entryT[3], exitT[3];
    for (int axis = 0; axis < 3; ++axis) {
      const uint32_t nearByte = r.nearByte[axis], farByte = nearByte ^ uint32_t(N * sizeof(float));
      entryT[axis] = (r.org[axis] - FN::load(reinterpret_cast<const float*>(rows + nearByte))) * r.negInv[axis];
      exitT[axis] = (r.org[axis] - FN::load(reinterpret_cast<const float*>(rows + farByte))) * r.negInv[axis];
      // Along an axis where the direction is +-0, -1/dir is -+inf, the entry plane is the one the
      // sign bit picks, and the distances are -inf / +inf inside the slab and +inf / -inf beyond a
      // plane: exact. An origin on a plane gives 0 * inf, the default NaN, whose sign bit is set:
      // a neutral entry, and an exit that min turns into +inf (minps returns its second operand
      // for a NaN), so the slab holds its boundary, as the float form's inside test does. A NaN
      // exit of an unused lane becomes +inf as well; its entry along an axis the ray moves along
      // stays a positive NaN and fails it.
      if constexpr (kForm == NodeTestForm::kBitsZeroAxes)
        exitT[axis] = min(exitT[axis], FN::broadcast(std::numeric_limits<float>::infinity()));
    }
    const FN nearT = maxOfBits(maxOfBits(entryT[0], entryT[1]), maxOfBits(r.tnear, entryT[2]));
    // near <= min(exit + k, tfar) (k = kConservativeFarUlps, on the bits) is tested as
    // min(exit, tfar - k) > near - (k + 1): the same lanes (no term wraps: near >= tnear >= +0, and
    // a negative tfar becomes the smallest integer, entering nothing), with the add moved off the
    // exits' chain and the compare's sense already the entered mask: the exits' chain from the
    // multiplies to the mask shrank from five steps and two scalar ones to three.
    const FN farT = minOfBits(minOfBits(exitT[0], exitT[1]), minOfBits(exitT[2], tfarLanes));
    nearT.store(entry);
    return bitsGreaterMask(farT, bitsPlusLanes(nearT, r.nearAllowance));
  } else {
    FN nearT = r.tnear;
    FN farT = FN::broadcast(std::numeric_limits<float>::infinity());
    int inside = (1 << N) - 1;
    for (int axis = 0; axis < 3; ++axis) {
      const FN lower = FN::load(node.bounds[axis * 2]);
      const FN upper = FN::load(node.bounds[axis * 2 + 1]);
      if ((r.zeroAxes >> axis) & 1) {
        inside &= lessEqualMask(lower, r.org[axis]) & lessEqualMask(r.org[axis], upper);
        continue;
      }
      // Operand order: a NaN (NaN ray or unused lane) lands in nearT/farT and fails the compare.
      const FN t0 = (r.org[axis] - lower) * r.negInv[axis];
      const FN t1 = (r.org[axis] - upper) * r.negInv[axis];
      nearT = max(nearT, min(t0, t1));
      farT = min(farT, max(t0, t1));
    }
    farT = min(farT * FN::broadcast(kConservativeFarScale), tfarLanes);
    nearT.store(entry);
    return lessEqualMask(nearT, farT) & inside;
  }
}

// Children are visited one after the other; loading the next ones' first cache lines early
// hides part of the memory latency that dominates incoherent rays. Always inlined: as a call, GCC
// found the function free of side effects (a prefetch has none) and deleted every call from the
// single-ray kernels before inlining could keep them (the prefetches were missing from those
// kernels until this was found).
template <typename FN>
[[gnu::always_inline]] inline void prefetchChild(const TriangleWideView<FN::kWidth>& bvh, uint32_t child) {
  using Node = WideNode<FN::kWidth>;
  // Constant trip counts, so both loops unroll into bare prefetch instructions.
  if (Node::isLeaf(child)) {
    const char* p = reinterpret_cast<const char*>(bvh.blocks + Node::leafFirstBlock(child));
    for (size_t line = 0; line < sizeof(TriangleBlock4); line += 64) __builtin_prefetch(p + line);
  } else {
    const char* p = reinterpret_cast<const char*>(bvh.nodes + child);
    for (size_t line = 0; line < sizeof(Node); line += 64) __builtin_prefetch(p + line);
  }
}

// The axis-aligned layouts' nodes as the shared walk (wide_walk.h) sees them.
template <typename FN, NodeTestForm kForm>
struct AxisAlignedWideNodes {
  const TriangleWideView<FN::kWidth>& bvh;
  const WideRayFrame<FN>& frame;
  // A copy of bvh.nodes: read through the view, the pointer was loaded again at every node (the
  // leaf test, a call, might have changed the view for all the compiler knew).
  const WideNode<FN::kWidth>* nodes = bvh.nodes;
  // The integer forms' entries are at least tnear, +0 or positive (see intersectWideNode).
  static constexpr bool kEntriesNonNegative = kForm != NodeTestForm::kFloat;
  const uint32_t* children(uint32_t node) const { return nodes[node].child; }
  [[gnu::always_inline]] FN exitLimit(float tfar) const { return exitLimitLanes<kForm, FN>(tfar); }
  [[gnu::always_inline]] int enter(uint32_t node, float /*tnear: the frame's*/, const FN& tfarLanes,
                                   float entry[FN::kWidth]) const {
    return intersectWideNode<kForm>(nodes[node], frame, tfarLanes, entry);
  }
  [[gnu::always_inline]] void prefetch(uint32_t child) const { prefetchChild<FN>(bvh, child); }
  void count(uint32_t, TraversalCounters& counters) const { counters.aabbTests += FN::kWidth; }
};

// Visits the leaves the ray enters from node start (a packet hands a ray over to it mid-tree);
// see walkWideTree (kPredictLanes: for rays the application declared coherent, QueryState;
// onEntering: the leaves' set-up, once the ray is known to enter the tree). kForm: the frame's
// form (nodeTestFormOf).
template <NodeTestForm kForm, typename FN, bool kClosest, bool kCounted = false, bool kSorted = kClosest,
          bool kPredictLanes = false, typename LeafVisitor, typename OnEntering = NothingOnEntering>
[[gnu::always_inline]] inline void traverseWideInForm(const TriangleWideView<FN::kWidth>& bvh, uint32_t start,
                                                    const WideRayFrame<FN>& frame, const Ray& ray,
                                                    LeafVisitor&& leafVisitor, TraversalCounters* counters,
                                                    OnEntering&& onEntering) {
  walkWideTree<FN::kWidth, kClosest, kCounted, kSorted, kPredictLanes>(AxisAlignedWideNodes<FN, kForm>{bvh, frame}, start,
                                                                       ray, leafVisitor, counters, onEntering);
}

// The same for a frame of either form other than NodeTestForm::kBits (traverseWide takes that one
// apart, so that its kernels hold one copy of each walk).
template <typename FN, bool kClosest, bool kCounted = false, bool kSorted = kClosest, bool kPredictLanes = false,
          typename LeafVisitor, typename OnEntering = NothingOnEntering>
[[gnu::always_inline]] inline void traverseWideInOtherForms(const TriangleWideView<FN::kWidth>& bvh, uint32_t start,
                                                          const WideRayFrame<FN>& frame, const Ray& ray,
                                                          LeafVisitor&& leafVisitor, TraversalCounters* counters,
                                                          OnEntering&& onEntering) {
  if (nodeTestFormOf(frame) == NodeTestForm::kFloat)
    return traverseWideInForm<NodeTestForm::kFloat, FN, kClosest, kCounted, kSorted, kPredictLanes>(
        bvh, start, frame, ray, leafVisitor, counters, onEntering);
  return traverseWideInForm<NodeTestForm::kBitsZeroAxes, FN, kClosest, kCounted, kSorted, kPredictLanes>(
      bvh, start, frame, ray, leafVisitor, counters, onEntering);
}

// Any frame's form, chosen at the ray.
template <typename FN, bool kClosest, bool kCounted = false, bool kSorted = kClosest, bool kPredictLanes = false,
          typename LeafVisitor, typename OnEntering = NothingOnEntering>
[[gnu::always_inline]] inline void traverseWideFrom(const TriangleWideView<FN::kWidth>& bvh, uint32_t start,
                                                  const WideRayFrame<FN>& frame, const Ray& ray,
                                                  LeafVisitor&& leafVisitor, TraversalCounters* counters = nullptr,
                                                  OnEntering&& onEntering = {}) {
  if (nodeTestFormOf(frame) == NodeTestForm::kBits)
    return traverseWideInForm<NodeTestForm::kBits, FN, kClosest, kCounted, kSorted, kPredictLanes>(
        bvh, start, frame, ray, leafVisitor, counters, onEntering);
  return traverseWideInOtherForms<FN, kClosest, kCounted, kSorted, kPredictLanes>(bvh, start, frame, ray, leafVisitor,
                                                                                  counters, onEntering);
}

// Always inlined into the kernel that calls it: as a call of its own (GCC kept it out of line) it
// took a second prologue, and the leaf visitor's captures went through a closure in memory; miss
// rays, which spend their time in such fixed costs, traced 8% faster inlined (bunny primary rays).
template <typename FN, bool kClosest, bool kCounted = false, bool kSorted = kClosest, bool kPredictLanes = false,
          typename LeafVisitor, typename OnEntering = NothingOnEntering>
[[gnu::always_inline]] inline void traverseWide(const TriangleWideView<FN::kWidth>& bvh, const Ray& ray,
                                                LeafVisitor&& leafVisitor, TraversalCounters* counters = nullptr,
                                                OnEntering&& onEntering = {}) {
  using Node = WideNode<FN::kWidth>;
  if (bvh.empty()) return;
  if (Node::isLeaf(bvh.root)) {
    if constexpr (kCounted) ++counters->leafVisits;
    onEntering();
    leafVisitor(Node::leafFirstBlock(bvh.root), Node::leafBlockCount(bvh.root));
    return;
  }
  // An empty segment enters nothing (the walk's first test), known before the frame's set-up: the
  // benchmark's shadow rays from primary rays that missed are such rays (tfar < tnear).
  if (ray.tnear > ray.tfar) return;
  const RayDirection<typename FN::Lanes4> direction(ray);
  if (direction.integerForm) {
    // Closest-hit rays only: any-hit ones (shadow rays from surface points) start inside the box,
    // where the check only costs (motorBike shadow rays 3% slower with it). The counted walks keep
    // the root node's test, whose box tests they count.
    if constexpr (kClosest && !kCounted) {
      if (missesRootBox<FN>(bvh, ray, direction)) return;
    }
    const WideRayFrame<FN> frame = WideRayFrame<FN>::ofIntegerForm(ray, direction);
    return traverseWideInForm<NodeTestForm::kBits, FN, kClosest, kCounted, kSorted, kPredictLanes>(
        bvh, bvh.root, frame, ray, leafVisitor, counters, onEntering);
  }
  const WideRayFrame<FN> frame(ray, direction);
  traverseWideInOtherForms<FN, kClosest, kCounted, kSorted, kPredictLanes>(bvh, bvh.root, frame, ray, leafVisitor,
                                                                           counters, onEntering);
}

// kSorted: children near to far, else in lane order (ChildOrder). kPredictLanes: the walk for rays
// the application declared coherent (QueryState::coherent). The leaf visitor is forced inline
// (GCC kept it out of line: a call per leaf visit, with the frame's vector registers spilled around
// it): diffuse bounces 2-3.5% faster on the bunny, motorBike and dragon (one thread, best of 11, two
// alternations), camera and random rays within noise. The any-hit kernel keeps the call (inlined,
// shadow rays measured 0.99-1.03x).
template <typename FN, typename F4, bool kCounted = false, bool kSorted = true, bool kPredictLanes = false>
bool intersectClosestWideImpl(const TriangleWideView<FN::kWidth>& bvh, Ray& ray, Hit& hit, const QueryState& state) {
  WatertightRayOnEntering watertight;
  bool found = false;
  traverseWide<FN, true, kCounted, kSorted, kPredictLanes>(bvh, ray, [&](uint32_t firstBlock, uint32_t blockCount)
                                                                           __attribute__((always_inline)) {
    const bool shortened = intersectBlocksClosest<F4, simd::DoubleLanes<FN>, !kPredictLanes>(
        bvh.set, bvh.blocks, firstBlock, blockCount, watertight.get(), ray, hit, state);
    found |= shortened;
    return shortened;
  }, state.counters, watertight.maker(ray, bvh.set));
  return found;
}

template <typename FN, typename F4, bool kCounted = false, bool kPredictLanes = false>
bool intersectAnyWideImpl(const TriangleWideView<FN::kWidth>& bvh, const Ray& ray, const QueryState& state) {
  WatertightRayOnEntering watertight;
  bool found = false;
  traverseWide<FN, false, kCounted, false, kPredictLanes>(bvh, ray, [&](uint32_t firstBlock, uint32_t blockCount) {
    found = intersectBlocksAny<F4, simd::DoubleLanes<FN>>(bvh.set, bvh.blocks, firstBlock, blockCount,
                                                          watertight.get(), ray, state);
    return found;
  }, state.counters, watertight.maker(ray, bvh.set));
  return found;
}

}  // namespace obvh
