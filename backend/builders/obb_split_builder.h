// Binary BVH whose splits are chosen along the axes of each node's own oriented box (DiTO-14):
// binned SAH over boxes in that frame, the object median, or the spatial midpoint. Slanted
// geometry then splits along its own directions instead of the world's.
#pragma once

#include <vector>

#include "builders/build_options.h"
#include "builders/prim_ref.h"
#include "bvh/binary_bvh.h"
#include "intersect/triangle.h"

namespace obvh {

// refs index `triangles`; options.obbSplit (not AabbSah), obbBins, maxLeafSize and the costs apply.
// The returned tree's node bounds are world AABBs; primIndices hold PrimRef::index values.
BinaryBvh buildInObbFrames(PrimRefs& refs, const StoredTriangle* triangles, const BuildOptions& options);

}  // namespace obvh
