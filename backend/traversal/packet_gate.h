// A packet's first test, before anything is made for it: which of its lanes certainly miss the box
// around the root node's children. Rays outside the tree's box (most of a camera's rays over a
// single object: 52% of the bench's bunny packets and 81% of its motorBike ones missed the root
// node whole) then cost a packet no gather, no lane set-up and no root node test, as each such ray
// alone already skips them (missesRootBox, wide_traverse.h).
// Templates on a lane type F (Float4Sse, Float8Avx, FloatScalar<N>), always inlined into the
// caller's instruction set.
#pragma once

#include <limits>

#include "traversal/box_test.h"
#include "traversal/query_entry.h"

namespace obvh {

// The lanes of `lanes` whose ray enters no child of the root node by the node tests of both walks
// (the packet's per-ray lane test, PacketLanes::intersectNode, and the single ray's integer form,
// intersectWideNode), because it misses the box around those children. The same operations on the
// box's planes: they lie outside every child's, and each step (rounded subtraction and
// multiplication, the maxima and minima on the bits, the allowance of ulps) is monotone, so the box's
// entry is no later and its exit no earlier than any child's. Along an axis a ray does not move
// along (direction +-0) those tests' forms with zero axes put it inside a slab exactly when its
// origin lies within [lower, upper]: here such an axis gives no exit and, for an origin outside,
// a positive entry (rounded differences keep their sign, and zero only for equal operands), which
// may still fall within the segment but never turns away a ray inside. A ray whose origin is not a
// number enters no child either (see missesRootBox). Rays those tests take in another form (tnear
// negative, -0, not finite or NaN; 1/dir infinite or NaN without a zero direction, or zero) are
// never turned away here, nor is any ray by a gate that is not bounded. The choices are made on
// lanes (blends on sign bits) rather than bit masks: with a mask blend for each, the test took 150
// instructions a packet of eight, as much as the packets it turned away saved (callgrind).
template <typename F>
[[gnu::always_inline]] inline int lanesMissingGate(const PacketGate& gate, const F org[3], const F dir[3],
                                                   const F& tnear, const F& tfar, int lanes) {
  if (!gate.bounded) return 0;
  const F zero = F::broadcast(0.f), infinity = F::broadcast(std::numeric_limits<float>::infinity());
  const F largest = F::broadcast(std::numeric_limits<float>::max());
  // tnear +0 or positive and finite (bitsLessEqualMask: -0 fails, as in tnearAllowsIntegerForm).
  int testable = bitsLessEqualMask(zero, tnear) & lessMask(tnear, infinity);
  F nearT = tnear, exit = infinity;
  for (int axis = 0; axis < 3; ++axis) {
    const F negInv = zero - F::broadcast(1.f) / dir[axis];
    const F size = abs(negInv);
    testable &= (lessMask(size, infinity) & ~equalMask(negInv, zero)) | equalMask(dir[axis], zero);
    const F toLower = org[axis] - F::broadcast(gate.lower[axis]), toUpper = org[axis] - F::broadcast(gate.upper[axis]);
    const F lowerT = toLower * negInv, upperT = toUpper * negInv;
    // Sign bit set where 1/dir is infinite: the lanes that do not move along the axis.
    const F still = largest - size;
    const F outside = max(zero - toLower, toUpper) * largest;  // positive only outside [lower, upper]
    nearT = maxOfBits(nearT, selectBySign(still, min(lowerT, upperT), outside));
    exit = minOfBits(exit, selectBySign(still, max(lowerT, upperT), infinity));
  }
  const F farT = minOfBits(bitsPlus(exit, kConservativeFarUlps), tfar);
  return ~bitsLessEqualMask(nearT, farT) & testable & lanes;
}

}  // namespace obvh
