// A mesh of the tools' scene description as the backend's MeshDesc (pointers into the mesh, which
// must outlive the description). For code that drives obvh's backend directly (the layout study,
// backend tests); it needs the backend's include path.
#pragma once

#include <cstdint>

#include "math/vec3.h"
#include "scene/mesh_desc.h"
#include "scene/scene_desc.h"
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

// Every mesh of the scene, geometry IDs in order.
inline SceneDesc backendSceneDesc(const SceneData& scene) {
  SceneDesc desc;
  for (size_t g = 0; g < scene.meshes.size(); ++g) desc.meshes.push_back(backendMeshDesc(scene.meshes[g], uint32_t(g)));
  desc.geometryIdLimit = uint32_t(scene.meshes.size());
  return desc;
}

// The box of every vertex of the scene's meshes.
inline Box3f backendSceneBounds(const SceneData& scene) {
  Box3f box;
  for (const MeshData& mesh : scene.meshes)
    for (size_t i = 0; i + 2 < mesh.vertices.size(); i += 3)
      box.extend(Vec3f{mesh.vertices[i], mesh.vertices[i + 1], mesh.vertices[i + 2]});
  return box;
}

}  // namespace obvh::tools
