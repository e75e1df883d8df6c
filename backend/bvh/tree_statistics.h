// The SAH cost of a committed tree as Embree's statistics report it (rtcNewDevice "verbose=2",
// line "total : sah = ..."), so the two libraries' trees can be compared by one number: every
// node counts its surface area relative to the root's, times one for an interior node and times
// its number of four-triangle blocks for a leaf.
#pragma once

#include "bvh/binary_bvh.h"
#include "bvh/wide_bvh.h"

namespace obvh {

template <int N>
double statisticsSah(const WideBvh<N>& bvh);

// A binary tree: leaves count ceil(primitives / 4) blocks, as if stored in four-triangle blocks.
double statisticsSah(const BinaryBvh& bvh);

extern template double statisticsSah<4>(const WideBvh<4>&);
extern template double statisticsSah<8>(const WideBvh<8>&);

}  // namespace obvh
