// Turns mesh descriptions into the triangles a BVH stores, skipping invalid primitives as Embree does.
#pragma once

#include <vector>

#include "builders/prim_ref.h"
#include "intersect/triangle.h"
#include "scene/mesh_desc.h"

namespace obvh {

// Embree treats a vertex as invalid when it is not finite or its magnitude reaches this value.
constexpr float kLargestValidCoordinate = 1.844e18f;

struct CollectedPrimitives {
  std::vector<StoredTriangle> triangles;  // refs[i].index indexes this table
  std::vector<PrimRef> refs;
  std::vector<GridCell> gridCells;        // the cells of every grid, indexed by their triangles' primID
};

// A primitive is skipped when an index is out of range or one of its vertices is invalid; a grid
// is skipped whole when one of its vertices is (as Embree does), and has no cells when its width or
// height is below 2.
CollectedPrimitives collectPrimitives(const std::vector<MeshDesc>& meshes);

}  // namespace obvh
