// Plain description of one triangle or quad mesh, as the API layer hands it to the backend.
#pragma once

#include <cstddef>
#include <cstdint>

namespace obvh {

struct MeshDesc {
  const unsigned char* vertices = nullptr;  // float x, y, z at each stride
  size_t vertexStride = 0;
  size_t vertexCount = 0;
  const unsigned char* indices = nullptr;   // uint32 x 3 (triangles) or x 4 (quads) at each stride
  size_t indexStride = 0;
  size_t primCount = 0;
  bool quads = false;
  uint32_t geomID = 0;
  uint32_t mask = 0xFFFFFFFFu;
};

}  // namespace obvh
