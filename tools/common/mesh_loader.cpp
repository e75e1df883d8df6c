#include "mesh_loader.h"

#include <tiny_obj_loader.h>

#include <algorithm>
#include <cctype>

#include <fstream>
#include <stdexcept>

#include "ply_reader.h"
#include "stl_reader.h"

namespace obvh::tools {

SceneData loadObj(const std::string& path) {
  if (!std::ifstream(path).good()) throw std::runtime_error("cannot open mesh file '" + path + "'");
  tinyobj::ObjReaderConfig config;
  config.triangulate = true;
  config.vertex_color = false;
  tinyobj::ObjReader reader;
  if (!reader.ParseFromFile(path, config))
    throw std::runtime_error("cannot parse OBJ '" + path + "': " + reader.Error());
  const tinyobj::attrib_t& attrib = reader.GetAttrib();
  if (attrib.vertices.empty()) throw std::runtime_error("OBJ '" + path + "' has no vertices");

  SceneData scene;
  scene.name = path.substr(path.find_last_of('/') + 1);
  MeshData mesh;
  mesh.vertices.assign(attrib.vertices.begin(), attrib.vertices.end());
  const size_t vertexCount = mesh.vertexCount();
  for (const tinyobj::shape_t& shape : reader.GetShapes())
    for (const tinyobj::index_t& index : shape.mesh.indices) {
      if (index.vertex_index < 0 || size_t(index.vertex_index) >= vertexCount)
        throw std::runtime_error("OBJ '" + path + "' references a vertex that does not exist");
      mesh.indices.push_back(uint32_t(index.vertex_index));
    }
  if (mesh.indices.empty()) throw std::runtime_error("OBJ '" + path + "' has no faces");
  scene.meshes.push_back(std::move(mesh));
  return scene;
}

std::string lowerCaseExtension(const std::string& path) {
  std::string extension = path.substr(path.find_last_of('.') + 1);
  std::transform(extension.begin(), extension.end(), extension.begin(), [](unsigned char c) { return char(std::tolower(c)); });
  return extension;
}

SceneData loadMesh(const std::string& path) {
  const std::string extension = lowerCaseExtension(path);
  if (extension == "obj") return loadObj(path);
  if (extension == "ply" || extension == "stl") {
    SceneData scene;
    scene.name = path.substr(path.find_last_of('/') + 1);
    scene.meshes.push_back(extension == "ply" ? readPly(path) : readStl(path));
    return scene;
  }
  throw std::runtime_error("cannot load '" + path + "': obvh reads .obj, .ply and .stl meshes");
}

}  // namespace obvh::tools
