// Distance-aware SAH builder (device config builder=distance), for rays launched from a known
// point such as a radio transmitter. Each split minimises
//   alpha * SAH + (1 - alpha) * SAH_source
// SAH weighs each child by its surface area (the chance that a ray from anywhere enters it);
// SAH_source weighs it by the chance that a ray from the source enters it: the solid angle the
// child subtends, about its area over d^2, d the distance of the child's centre from the source
// (and 1 once the source is about as close as the child is large). Both are relative to leaving
// the node unsplit. Near the source every ray enters a node, so there the builder gathers few
// primitives into small nodes; far away it accepts large ones. alpha = 1 is plain binned SAH.
// (An additive "+ d^2 of the nearer child" term was tried first: it pulls the split towards the
// source one slab at a time and leaves the primitives around the source deeper, not shallower.)
#pragma once

#include <vector>

#include "builders/build_options.h"
#include "builders/prim_ref.h"
#include "bvh/binary_bvh.h"

namespace obvh {

// Reorders refs; the tree's primIndices hold PrimRef::index values in leaf order. Deterministic
// for any thread count. Uses options.distanceAlpha and options.distanceSource.
BinaryBvh buildDistanceSah(PrimRefs& refs, const BuildOptions& options);

}  // namespace obvh
