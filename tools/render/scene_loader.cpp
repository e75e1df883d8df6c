#include "scene_loader.h"

#include <cmath>
#include <stdexcept>

#include "mesh_loader.h"

namespace obvh::render {
namespace {

// OBJ and PLY carry one mesh without materials, lights or camera: placed once, default material.
RenderScene meshFileScene(const std::string& path) {
  const tools::SceneData data = tools::loadMesh(path);
  RenderScene scene;
  scene.name = data.name;
  for (const tools::MeshData& in : data.meshes) {
    Primitive p;
    p.positions = in.vertices;
    for (float v : p.positions)
      if (!std::isfinite(v)) throw std::runtime_error("mesh '" + path + "' has a non-finite vertex position");
    if (in.quads) {
      for (size_t q = 0; q < in.primitiveCount(); ++q) {
        const uint32_t* i = &in.indices[4 * q];
        p.indices.insert(p.indices.end(), {i[0], i[1], i[2], i[0], i[2], i[3]});
      }
    } else {
      p.indices = in.indices;
    }
    Mesh mesh;
    mesh.name = scene.name;
    mesh.primitives.push_back(std::move(p));
    Node node;
    node.mesh = int(scene.meshes.size());
    scene.roots.push_back(int(scene.nodes.size()));
    scene.nodes.push_back(node);
    scene.meshes.push_back(std::move(mesh));
  }
  return scene;
}

}  // namespace

RenderScene loadRenderScene(const std::string& path) {
  const std::string extension = tools::lowerCaseExtension(path);
  if (extension == "gltf" || extension == "glb") return loadGltfScene(path);
  if (extension == "obj" || extension == "ply" || extension == "stl") return meshFileScene(path);
  throw std::runtime_error("cannot render '" + path + "': obvh_render reads .gltf, .glb, .obj, .ply and .stl");
}

}  // namespace obvh::render
