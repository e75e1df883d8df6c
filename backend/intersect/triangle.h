// Triangles as stored in the acceleration structure, in leaf order.
#pragma once

#include <cstdint>

#include "math/vec3.h"

namespace obvh {

// Quads are stored as two triangles: (v0,v1,v3) and (v2,v3,v1). The second one reports
// u' = 1-u, v' = 1-v so that both halves share the quad's (u,v) parameterisation.
enum class TriangleKind : uint32_t { Triangle = 0, QuadFirstHalf = 1, QuadSecondHalf = 2 };

struct StoredTriangle {
  Vec3f v0, v1, v2;
  uint32_t geomID = 0;
  uint32_t primID = 0;
  TriangleKind kind = TriangleKind::Triangle;
};

}  // namespace obvh
