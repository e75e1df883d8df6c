// Plain description of one triangle, quad or grid mesh, as the API layer hands it to the backend.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "intersect/triangle.h"

namespace obvh {

enum class MeshTopology : uint8_t {
  Triangles,  // uint32 x 3 per primitive
  Quads,      // uint32 x 4 per primitive
  Grids,      // Embree's RTCGrid per primitive: uint32 startVertexID, uint32 stride, uint16 width, height
  SubdivCells // a subdivision surface's tessellation: uint32 x 4 cell corners per primitive, with subdivCells
};

struct MeshDesc {
  const unsigned char* vertices = nullptr;  // float x, y, z at each stride
  size_t vertexStride = 0;
  size_t vertexCount = 0;
  const unsigned char* indices = nullptr;   // one primitive (as topology says) at each stride
  size_t indexStride = 0;
  size_t primCount = 0;
  MeshTopology topology = MeshTopology::Triangles;
  uint32_t geomID = 0;
  uint32_t mask = 0xFFFFFFFFu;
  const SubdivCell* subdivCells = nullptr;  // SubdivCells: each primitive's face and (u, v)
  // Motion blur: the vertices of every time step (vertices is the first), each laid out as
  // vertices is; empty for a mesh with one time step. The steps span [timeStart, timeEnd].
  std::vector<const unsigned char*> timeStepVertices;
  float timeStart = 0.f, timeEnd = 1.f;
  bool moving() const { return timeStepVertices.size() > 1; }
};

}  // namespace obvh
