// A face of a subdivision surface with the faces around its corners (its 1-ring), carrying any
// number of values per vertex (positions, attributes). One Catmull-Clark step of the ring holds
// the 1-rings of the face's four children, so a point of the face is evaluated by subdividing
// towards it until its child is a regular bicubic B-spline patch.
#pragma once

#include <cstddef>
#include <cstdint>
#include <unordered_map>
#include <vector>

#include "subdiv/subdiv_topology.h"

namespace obvh {

struct LocalPatch {
  int dim = 3;                          // values per vertex
  std::vector<double> values;           // vertexCount() * dim
  std::vector<float> vertexSharpness;   // per vertex
  std::vector<uint32_t> faceStart{0};   // face f: faceVertices[faceStart[f], faceStart[f + 1])
  std::vector<int> faceVertices;        // face 0 is the patch's own face
  std::unordered_map<uint64_t, float> edgeSharpness;  // only edges of non-zero sharpness

  int vertexCount() const { return int(vertexSharpness.size()); }
  int faceCount() const { return int(faceStart.size()) - 1; }
  const double* value(int v) const { return values.data() + size_t(v) * dim; }
  float sharpness(int a, int b) const;
};

// Reads `dim` values of a control vertex (a position, or an attribute).
using ControlValues = void (*)(const void* context, uint32_t vertex, double* out);

// The 1-ring of face f of the control mesh.
LocalPatch ringOfFace(const SubdivTopology& topology, uint32_t face, int dim, ControlValues read,
                      const void* context);

// One Catmull-Clark step of the whole patch (values next to its rim are not meaningful); face i of
// the result is child i of face 0 (at its vertex i) for i below face 0's size.
LocalPatch subdivide(const LocalPatch& patch);
// The 1-ring of one child of face 0 of `patch`, from `subdivided` = subdivide(patch): for a quad
// face, the child of quadrant (qu, qv) in [0,1]^2, ordered so that its (u, v) run along its
// parent's; for a face of n vertices, the child at vertex `corner`, its u towards the next vertex
// and its v towards the previous one.
LocalPatch quadrantChild(const LocalPatch& subdivided, int qu, int qv);
LocalPatch cornerChild(const LocalPatch& subdivided, int corner);

// The 16 B-spline control points of face 0 (row r along v, column c along u), when the face is a
// regular quad: its corners are smooth vertices of valence 4, or lie on infinitely sharp creases
// or boundaries that run along its edges (then mirrored control points stand in for the other
// side), with no other sharpness nearby.
bool regularControlGrid(const LocalPatch& patch, std::vector<double>& grid);

// Limit positions of face 0's four corners (face 0 must be a quad whose neighbours are quads).
void cornerLimits(const LocalPatch& patch, std::vector<double>& corners);

}  // namespace obvh
