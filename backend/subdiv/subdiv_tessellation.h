// A subdivision surface cut into the grids Embree 3 traces: each quad face a grid of
// max(ceil(level)) cells along u and v (levels per edge, or the tessellation rate), the points on
// an edge of fewer segments snapped to that edge's own segments; any other face one grid per
// subpatch (the quads of one subdivision step) at half the levels. Grid points lie on the limit
// surface; points shared by faces are evaluated once, so the tessellation has no cracks.
#pragma once

#include <cstdint>
#include <vector>

#include "intersect/triangle.h"
#include "math/vec3.h"
#include "subdiv/local_patch.h"
#include "subdiv/subdiv_topology.h"

namespace obvh {

struct SubdivTessellation {
  std::vector<Vec3f> vertices;
  std::vector<uint32_t> cellCorners;  // four per cell: (i, j), (i + 1, j), (i + 1, j + 1), (i, j + 1)
  std::vector<SubdivCell> cells;      // the face and (u, v) at the corners of each cell
};

// Segments along an edge of tessellation level `level` (Embree rounds up, at least 1, at most 4096).
int edgeSegments(float level);

// levels: one per half-edge (Embree's level buffer), or null to use `rate` everywhere.
SubdivTessellation tessellateSubdivision(const SubdivTopology& topology, ControlValues readPosition,
                                         const void* context, const float* levels, float rate);

}  // namespace obvh
