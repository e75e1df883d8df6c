// k-means k-ary BVH builder (device config builder=kmeans): each node's primitives are clustered
// by their centroids into k groups (Lloyd's algorithm), and every group becomes a child. No
// surface-area evaluation: an alternative to binned SAH that the benchmark compares against it.
#pragma once

#include <vector>

#include "builders/build_options.h"
#include "builders/prim_ref.h"
#include "bvh/binary_bvh.h"

namespace obvh {

// Reorders refs; the tree's primIndices hold PrimRef::index values in leaf order. The k clusters
// of a node hang below it as a small binary tree, so the wide collapse (which opens the largest
// child first) turns them back into one k-wide node. Deterministic for any thread count.
BinaryBvh buildKMeans(PrimRefs& refs, const BuildOptions& options);

}  // namespace obvh
