// Rebuilds the small subtrees of a binary tree (treelets of at most kMaxTreeletTriangles) with the
// SAH evaluated in each node's own oriented box (DiTO-14). The axis-aligned SAH that builds the
// oriented layouts' topology (obb_split=aabb) measures slanted triangles by their world boxes,
// which cannot tell its groupings apart near the leaves: the top and bottom faces of a slanted
// line, each flat in the line's frame, came out as two leaves of one top and one bottom triangle
// each, both as large as the line, instead of a leaf per face, and a ray hitting the top face
// visited both. Rebuilt, the rays of small-1.5k's orthographic view that hit visit 1.23 leaves
// instead of 1.66.
#pragma once

#include "builders/build_options.h"
#include "bvh/binary_bvh.h"
#include "intersect/triangle.h"

namespace obvh {

// A slanted line is twelve triangles. Treelets of 8 and of 32 gave the stack presets about the same
// leaf visits as 16.
constexpr uint32_t kMaxTreeletTriangles = 16;

// triangles[bvh.primIndices[i]] is the triangle of leaf position i. Deterministic.
void rebuildTreeletsInOwnFrames(BinaryBvh& bvh, const StoredTriangle* triangles, const BuildOptions& options);

}  // namespace obvh
