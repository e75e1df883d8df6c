// Turns mesh descriptions into the triangles a BVH stores, skipping invalid primitives as Embree does.
#pragma once

#include <cmath>
#include <vector>

#include "builders/prim_ref.h"
#include "math/vec3.h"
#include "intersect/triangle.h"
#include "scene/mesh_desc.h"

namespace obvh {

// Embree treats a vertex as invalid when it is not finite or its magnitude reaches this value.
constexpr float kLargestValidCoordinate = 1.844e18f;
inline bool isValidVertex(const float xyz[3]) {
  for (int k = 0; k < 3; ++k)
    if (!(std::fabs(xyz[k]) < kLargestValidCoordinate)) return false;  // NaN fails too
  return true;
}

struct CollectedPrimitives {
  StoredTriangles triangles;  // refs[i].index indexes this table
  PrimRefs refs;
  std::vector<GridCell> gridCells;        // the cells of every grid, indexed by their triangles' primID
  std::vector<SubdivCell> subdivCells;    // the tessellation cells of subdivision surfaces, alike
};

// Triangles of motion-blurred meshes (more than one time step): their vertices at every step,
// interpolated linearly within the segment a ray's time falls in.
struct MotionTriangle {
  uint32_t geomID = 0, primID = 0;  // primID: a grid (subdivision) cell's index in CollectedMotion::gridCells (subdivCells)
  TriangleKind kind = TriangleKind::Triangle;
  uint32_t firstVertex = 0;         // three vertices per time step in CollectedMotion::vertices
  uint32_t stepCount = 2;
  float timeStart = 0.f, timeEnd = 1.f;

  // The triangle at `time`; false when its mesh is not there then (outside [timeStart, timeEnd]).
  bool at(const std::vector<Vec3f>& vertices, float time, StoredTriangle& out) const;
  // Bounds of every time step (and so of all times between).
  Box3f bounds(const std::vector<Vec3f>& vertices) const;
};

struct CollectedMotion {
  std::vector<MotionTriangle> triangles;
  std::vector<Vec3f> vertices;
  std::vector<GridCell> gridCells;
  std::vector<SubdivCell> subdivCells;
};

// A primitive is skipped when an index is out of range or one of its vertices is invalid; a grid
// is skipped whole when one of its vertices is (as Embree does), and has no cells when its width or
// height is below 2.
CollectedPrimitives collectPrimitives(const std::vector<MeshDesc>& meshes);

// The same for moving meshes (MeshDesc::moving()); a primitive invalid at any time step is skipped.
CollectedMotion collectMotionPrimitives(const std::vector<MeshDesc>& meshes);

}  // namespace obvh
