// Linear BVH builder for RTC_BUILD_QUALITY_LOW (after Lauterbach et al. 2009 and Karras 2012):
// primitives sorted along a 30-bit Morton curve of their centroids, the tree cut top-down at the
// highest bit in which a range's first and last codes differ. No surface-area evaluation at all:
// faster to build than binned SAH, slower to trace.
#pragma once

#include <vector>

#include "builders/build_options.h"
#include "builders/prim_ref.h"
#include "bvh/binary_bvh.h"

namespace obvh {

// Reorders refs; the tree's primIndices hold PrimRef::index values in leaf order. Deterministic:
// ties in the Morton code are ordered by the primitive index.
BinaryBvh buildMorton(PrimRefs& refs, const BuildOptions& options);

}  // namespace obvh
