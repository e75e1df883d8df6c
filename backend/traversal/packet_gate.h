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
// along (direction +-0) it is inside a slab exactly when its origin lies within [lower, upper], as
// those tests' forms with zero axes have it. Rays those tests take in another form (tnear negative,
// not finite or NaN, a NaN origin, 1/dir infinite, zero or NaN) are never turned away here, nor is
// any ray by a gate that is not bounded.
template <typename F>
[[gnu::always_inline]] inline int lanesMissingGate(const PacketGate& gate, const F org[3], const F dir[3],
                                                   const F& tnear, const F& tfar, int lanes) {
  if (!gate.bounded) return 0;
  const F zero = F::broadcast(0.f), infinity = F::broadcast(std::numeric_limits<float>::infinity());
  const F largest = F::broadcast(std::numeric_limits<float>::max());
  // tnear +0 or positive and finite (bitsLessEqualMask: -0 fails, as in tnearAllowsIntegerForm).
  int testable = bitsLessEqualMask(zero, tnear) & lessEqualMask(tnear, largest);
  int inside = ~0;
  F nearT = tnear, exit = infinity;
  for (int axis = 0; axis < 3; ++axis) {
    const F lower = F::broadcast(gate.lower[axis]), upper = F::broadcast(gate.upper[axis]);
    const int still = equalMask(dir[axis], zero);
    const F negInv = zero - F::broadcast(1.f) / dir[axis];
    const int finite = lessEqualMask(negInv, largest) & lessEqualMask(zero - largest, negInv) & ~equalMask(negInv, zero);
    testable &= equalMask(org[axis], org[axis]) & (still | finite);
    inside &= ~still | (lessEqualMask(lower, org[axis]) & lessEqualMask(org[axis], upper));
    const F toLower = (org[axis] - lower) * negInv, toUpper = (org[axis] - upper) * negInv;
    nearT = maxOfBits(nearT, select(still, zero, min(toLower, toUpper)));
    exit = minOfBits(exit, select(still, infinity, max(toLower, toUpper)));
  }
  const F farT = minOfBits(bitsPlus(exit, kConservativeFarUlps), tfar);
  const int enters = bitsLessEqualMask(nearT, farT) & inside;
  return ~enters & testable & lanes;
}

}  // namespace obvh
