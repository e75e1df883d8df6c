#include "triangle_scene_file.h"

#include <stdexcept>

#include "mesh_loader.h"
#include "render_scene.h"
#include "scene_loader.h"

namespace obvh::render {

tools::SceneData loadTriangleScene(const std::string& path) {
  const std::string extension = tools::lowerCaseExtension(path);
  if (extension != "gltf" && extension != "glb") return tools::loadMesh(path);
  const RenderScene scene = loadGltfScene(path);
  const ScenePose pose = poseAt(scene, 0.f);
  tools::MeshData flat;
  for (const PlacedMesh& placed : pose.meshes)
    for (const Primitive& primitive : scene.meshes[size_t(placed.mesh)].primitives) {
      const uint32_t first = uint32_t(flat.vertexCount());
      for (size_t v = 0; v < primitive.vertexCount(); ++v) {
        const Vec3 p = transformPoint(placed.toWorld, {primitive.positions[3 * v], primitive.positions[3 * v + 1],
                                                       primitive.positions[3 * v + 2]});
        flat.vertices.insert(flat.vertices.end(), {p.x, p.y, p.z});
      }
      for (uint32_t index : primitive.indices) flat.indices.push_back(first + index);
    }
  if (flat.indices.empty()) throw std::runtime_error("glTF '" + path + "' places no triangles in its scene");
  tools::SceneData data;
  data.name = path.substr(path.find_last_of('/') + 1);
  data.meshes.push_back(std::move(flat));
  return data;
}

}  // namespace obvh::render
