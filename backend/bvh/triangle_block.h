// Leaf triangles in groups of four, structure of arrays, so one SIMD test covers a whole group.
// A block carries everything a hit needs (vertices, ids, quad half), so testing a leaf touches
// only its blocks: no second lookup into the scene's triangle array.
#pragma once

#include <cstddef>
#include <cstdint>

#include "intersect/triangle.h"

namespace obvh {

struct alignas(64) TriangleBlock4 {
  static constexpr uint32_t kUnusedLane = 0xFFFFFFFFu;  // geomID of the padding lanes of a leaf's last block
  float v[3][3][4];  // v[vertex][axis][lane]
  uint32_t geomID[4];
  uint32_t primID[4];
  uint8_t kind[4];        // TriangleKind per lane (one byte keeps the block at three cache lines)
  uint8_t usedMask;       // bit per lane holding a triangle, read by every test of the block

  int usedLanes() const { return usedMask; }
  // Writes every field (no member starts initialized, so a table of blocks can be sized without
  // a fill): lanes [0, count) from triangles[first], triangles[first + 1], ..., 1 <= count <= 4
  // (triangles: anything indexable that yields a StoredTriangle, read in place: copied into a local
  // array first, four StoredTriangles' member initializers cost a 192-byte fill per block).
  // Padding lanes repeat the first triangle's vertices (finite arithmetic) and are left out of
  // usedMask.
  template <typename Triangles>
  void fill(const Triangles& triangles, size_t first, int count) {
    for (int lane = 0; lane < 4; ++lane) {
      const StoredTriangle& tri = triangles[first + size_t(lane < count ? lane : 0)];
      const Vec3f* corners[3] = {&tri.v0, &tri.v1, &tri.v2};
      for (int vertex = 0; vertex < 3; ++vertex)
        for (int axis = 0; axis < 3; ++axis) v[vertex][axis][lane] = (*corners[vertex])[axis];
      geomID[lane] = lane < count ? tri.geomID : kUnusedLane;
      primID[lane] = tri.primID;
      kind[lane] = uint8_t(tri.kind);
    }
    usedMask = uint8_t((1u << count) - 1);
  }
  Vec3f vertex(int k, int lane) const { return {v[k][0][lane], v[k][1][lane], v[k][2][lane]}; }
  StoredTriangle triangle(int lane) const {
    StoredTriangle tri;
    tri.v0 = vertex(0, lane);
    tri.v1 = vertex(1, lane);
    tri.v2 = vertex(2, lane);
    tri.geomID = geomID[lane];
    tri.primID = primID[lane];
    tri.kind = TriangleKind(kind[lane]);
    return tri;
  }
};
static_assert(sizeof(TriangleBlock4) == 192, "a block is three cache lines");

}  // namespace obvh
