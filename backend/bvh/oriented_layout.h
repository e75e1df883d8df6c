// Turns a binary tree into the oriented layouts: every node gets the DiTO-14 box of its triangles
// (accel=obb; nodes where the axis-aligned box is smaller stay axis-aligned), or whichever of its
// AABB and OBB gives the lower SAH cost once the OBB's dearer test is counted (accel=hybrid).
// With clusters > 0, leaf frames are grouped by k-means and each leaf is refitted in its
// cluster's frame, so leaves share frames and rays reuse their transform into them. With a
// palette > 0, every oriented node is refitted in the best of that many frames shared by the whole
// tree (k-means over the orientations of all oriented boxes), which the eight-wide kernels
// transform each ray into once.
#pragma once

#include "builders/build_options.h"
#include "bvh/binary_bvh.h"
#include "bvh/oriented_bvh.h"
#include "intersect/triangle.h"

namespace obvh {

// trianglesInLeafOrder[i] is the triangle of binary.primIndices[i].
OrientedBvh makeOrientedLayout(const BinaryBvh& binary, const StoredTriangle* trianglesInLeafOrder,
                               const BuildOptions& options);

LayoutMetrics measureLayout(const OrientedBvh& bvh, const BuildOptions& options);
LayoutMetrics measureLayout(const BinaryBvh& bvh, const BuildOptions& options);

}  // namespace obvh
