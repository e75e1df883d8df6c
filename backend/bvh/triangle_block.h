// Leaf triangles in groups of four, structure of arrays, so one SIMD test covers a whole group.
// A block carries everything a hit needs (vertices, ids, quad half), so testing a leaf touches
// only its blocks: no second lookup into the scene's triangle array.
#pragma once

#include <cstdint>

#include "intersect/triangle.h"

namespace obvh {

struct alignas(64) TriangleBlock4 {
  static constexpr uint32_t kUnusedLane = 0xFFFFFFFFu;  // geomID of the padding lanes of a leaf's last block
  float v[3][3][4];  // v[vertex][axis][lane]
  uint32_t geomID[4];
  uint32_t primID[4];
  TriangleKind kind[4];

  int usedLanes() const {
    int m = 0;
    for (int lane = 0; lane < 4; ++lane) m |= int(geomID[lane] != kUnusedLane) << lane;
    return m;
  }
  void setLane(int lane, const StoredTriangle& tri) {
    const Vec3f* corners[3] = {&tri.v0, &tri.v1, &tri.v2};
    for (int vertex = 0; vertex < 3; ++vertex)
      for (int axis = 0; axis < 3; ++axis) v[vertex][axis][lane] = (*corners[vertex])[axis];
    geomID[lane] = tri.geomID;
    primID[lane] = tri.primID;
    kind[lane] = tri.kind;
  }
  // Padding lanes repeat a used lane's vertices (finite arithmetic) and are masked out by geomID.
  void setUnusedLane(int lane, const StoredTriangle& someTriangle) {
    setLane(lane, someTriangle);
    geomID[lane] = kUnusedLane;
  }
  StoredTriangle triangle(int lane) const {
    StoredTriangle tri;
    tri.v0 = {v[0][0][lane], v[0][1][lane], v[0][2][lane]};
    tri.v1 = {v[1][0][lane], v[1][1][lane], v[1][2][lane]};
    tri.v2 = {v[2][0][lane], v[2][1][lane], v[2][2][lane]};
    tri.geomID = geomID[lane];
    tri.primID = primID[lane];
    tri.kind = kind[lane];
    return tri;
  }
};

}  // namespace obvh
