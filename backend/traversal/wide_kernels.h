// The kernel table of one pair of vector types (node width FN, four-lane triangle type F4): single
// rays and packets, closest and any hit. Each per-ISA file instantiates it inside its target region.
#pragma once

#include "traversal/wide_traverse.h"
#include "traversal/wide_traverse_packets.h"

namespace obvh {

template <typename FN, typename F4>
const WideKernels<FN::kWidth>& makeWideKernels() {
  static const WideKernels<FN::kWidth> kernels{&intersectClosestWideImpl<FN, F4>, &intersectAnyWideImpl<FN, F4>,
                                               &intersectClosestWidePacketImpl<FN, F4>,
                                               &intersectAnyWidePacketImpl<FN, F4>,
                                               &intersectClosestWideImpl<FN, F4, true>,
                                               &intersectAnyWideImpl<FN, F4, true>};
  return kernels;
}

}  // namespace obvh
