// Triangles as stored in the acceleration structure, in leaf order.
#pragma once

#include <cstdint>

#include "math/vec3.h"
#include "memory/unwritten_allocator.h"

namespace obvh {

// Quads are stored as two triangles: (v0,v1,v3) and (v2,v3,v1). The second one reports
// u' = 1-u, v' = 1-v so that both halves share the quad's (u,v) parameterisation. The cells of a
// grid (Embree's RTC_GEOMETRY_TYPE_GRID) are quads too, whose (u,v) then spans the whole grid.
enum class TriangleKind : uint32_t {
  Triangle = 0,
  QuadFirstHalf = 1,
  QuadSecondHalf = 2,
  GridFirstHalf = 3,
  GridSecondHalf = 4,
  SubdivFirstHalf = 5,
  SubdivSecondHalf = 6
};

inline bool isSecondHalf(TriangleKind kind) {
  return kind == TriangleKind::QuadSecondHalf || kind == TriangleKind::GridSecondHalf ||
         kind == TriangleKind::SubdivSecondHalf;
}
inline bool isGridCell(TriangleKind kind) {
  return kind == TriangleKind::GridFirstHalf || kind == TriangleKind::GridSecondHalf;
}

// Where a grid cell lies in its grid. The triangles of a grid cell carry the index of their cell in
// the scene's table of cells as primID (a block lane has no room for more), so that a hit can
// report the grid's primID and (u,v) across the grid.
struct GridCell {
  uint32_t gridPrimID = 0;
  uint16_t x = 0, y = 0;              // the cell's first vertex column and row
  uint16_t columns = 1, rows = 1;     // cells along u and v (the grid's width - 1, height - 1)
};

inline bool isSubdivCell(TriangleKind kind) {
  return kind == TriangleKind::SubdivFirstHalf || kind == TriangleKind::SubdivSecondHalf;
}

// A cell of a subdivision surface's tessellation (subdiv/subdiv_tessellation.h): its triangles carry
// the cell's index in the scene's table of cells as primID; a hit reports the face and the (u, v)
// interpolated from the cell's corners (in Embree's encoding for subpatches of non-quad faces).
struct SubdivCell {
  uint32_t facePrimID = 0;
  float u[4] = {0.f, 1.f, 1.f, 0.f}, v[4] = {0.f, 0.f, 1.f, 1.f};  // corners (i, j), (i+1, j), (i+1, j+1), (i, j+1)
};

struct StoredTriangle {
  Vec3f v0, v1, v2;
  uint32_t geomID = 0;
  uint32_t primID = 0;
  TriangleKind kind = TriangleKind::Triangle;
};

// A table of triangles; resize leaves the new triangles unwritten.
using StoredTriangles = UnwrittenVector<StoredTriangle>;

}  // namespace obvh
