// A mesh of the tools' scene description as the backend's MeshDesc (pointers into the mesh, which
// must outlive the description). For code that drives obvh's backend directly (the layout study,
// backend tests); it needs the backend's include path.
#pragma once

#include <cstdint>

#include "scene/mesh_desc.h"
#include "scene_data.h"

namespace obvh::tools {

inline MeshDesc backendMeshDesc(const MeshData& mesh, uint32_t geomID = 0) {
  MeshDesc desc;
  desc.vertices = reinterpret_cast<const unsigned char*>(mesh.vertices.data());
  desc.vertexStride = 3 * sizeof(float);
  desc.vertexCount = mesh.vertexCount();
  if (mesh.grid) {
    desc.indices = reinterpret_cast<const unsigned char*>(mesh.grids.data());
    desc.indexStride = sizeof(RTCGrid);
    desc.topology = MeshTopology::Grids;
  } else {
    desc.indices = reinterpret_cast<const unsigned char*>(mesh.indices.data());
    desc.indexStride = (mesh.quads ? 4 : 3) * sizeof(uint32_t);
    desc.topology = mesh.quads ? MeshTopology::Quads : MeshTopology::Triangles;
  }
  desc.primCount = mesh.primitiveCount();
  desc.geomID = geomID;
  return desc;
}

}  // namespace obvh::tools
