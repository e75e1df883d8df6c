// Spatial-split SAH builder (SBVH, Stich, Friedrich and Dietrich, "Spatial Splits in Bounding
// Volume Hierarchies", HPG 2009) for RTC_BUILD_QUALITY_HIGH: besides binned object splits, a node
// may cut space at a plane, sending a triangle that straddles it to both children with its bounds
// clipped to each side, so large or long slanted triangles stop inflating the boxes around them.
#pragma once

#include <vector>

#include "builders/build_options.h"
#include "builders/prim_ref.h"
#include "bvh/binary_bvh.h"
#include "intersect/triangle.h"

namespace obvh {

struct SpatialSplitSettings {
  // Extra references allowed, as a fraction of the triangle count. Embree allows 0.2; here 1.0 by
  // default (BuildOptions::spatialBudget): on slanted stacks 0.2 left the tree as it was, 1.0
  // halved the box tests per ray (README, build quality ladder).
  float referenceBudget = 1.0f;
  int spatialBins = 16;          // per axis, over the node's bounds
  float overlapThreshold = 1e-5f;  // try spatial splits only where the object split's children overlap this much of the root
};

// refs: one per triangle, index = position in `triangles`. The tree's primIndices may name a
// triangle more than once (in leaves on either side of a spatial split). Deterministic: the
// reference budget is handed down the tree in proportion to the children's sizes, never raced for.
BinaryBvh buildSpatialSah(const PrimRefs& refs, const StoredTriangle* triangles, const BuildOptions& options,
                          const SpatialSplitSettings& settings = {});

}  // namespace obvh
