// Binned surface-area-heuristic builder for a binary BVH (parallel with TBB).
#pragma once

#include <vector>

#include "builders/build_options.h"
#include "builders/prim_ref.h"
#include "bvh/binary_bvh.h"

namespace obvh {

// Reorders refs; the returned tree's primIndices hold PrimRef::index values in leaf order.
BinaryBvh buildBinnedSah(PrimRefs& refs, const BuildOptions& options);

}  // namespace obvh
