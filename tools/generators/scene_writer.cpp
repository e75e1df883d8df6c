#include "scene_writer.h"

#include <tiny_gltf.h>

#include <algorithm>
#include <cstring>
#include <fstream>
#include <limits>
#include <stdexcept>

namespace obvh::tools {
namespace {

void writeObj(const StackScene& scene, const std::string& path) {
  std::ofstream out(path);
  if (!out) throw std::runtime_error("cannot write '" + path + "'");
  out << "# " << scene.name << ": " << scene.triangleCount() << " triangles, written by obvh_stackgen\n";
  size_t base = 1;
  for (size_t g = 0; g < scene.groups.size(); ++g) {
    const MeshData& mesh = scene.groups[g];
    out << "o " << scene.groupNames[g] << "\n";
    for (size_t v = 0; v < mesh.vertexCount(); ++v)
      out << "v " << mesh.vertices[3 * v] << " " << mesh.vertices[3 * v + 1] << " " << mesh.vertices[3 * v + 2] << "\n";
    for (size_t f = 0; f < mesh.primitiveCount(); ++f)
      out << "f " << base + mesh.indices[3 * f] << " " << base + mesh.indices[3 * f + 1] << " "
          << base + mesh.indices[3 * f + 2] << "\n";
    base += mesh.vertexCount();
  }
  if (!out) throw std::runtime_error("writing '" + path + "' failed");
}

// Base colours per group, so that renders tell the parts apart.
std::vector<double> colourOf(const std::string& group) {
  if (group == "slabs") return {0.55, 0.6, 0.7, 1.0};
  if (group == "lines") return {0.85, 0.55, 0.25, 1.0};
  if (group == "vias") return {0.8, 0.8, 0.3, 1.0};
  if (group == "steps") return {0.4, 0.7, 0.45, 1.0};
  return {0.7, 0.35, 0.35, 1.0};
}

void writeGltf(const StackScene& scene, const std::string& path, bool binary) {
  tinygltf::Model model;
  model.asset.version = "2.0";
  model.asset.generator = "obvh_stackgen";
  tinygltf::Buffer buffer;
  tinygltf::Mesh mesh;
  mesh.name = scene.name;
  for (size_t g = 0; g < scene.groups.size(); ++g) {
    const MeshData& data = scene.groups[g];
    // Positions then indices, each in its own buffer view.
    const size_t positionOffset = buffer.data.size();
    const size_t positionBytes = data.vertices.size() * sizeof(float);
    buffer.data.resize(positionOffset + positionBytes);
    std::memcpy(buffer.data.data() + positionOffset, data.vertices.data(), positionBytes);
    const size_t indexOffset = buffer.data.size();
    const size_t indexBytes = data.indices.size() * sizeof(uint32_t);
    buffer.data.resize(indexOffset + indexBytes);
    std::memcpy(buffer.data.data() + indexOffset, data.indices.data(), indexBytes);

    tinygltf::BufferView positions;
    positions.buffer = 0, positions.byteOffset = positionOffset, positions.byteLength = positionBytes;
    positions.target = TINYGLTF_TARGET_ARRAY_BUFFER;
    tinygltf::BufferView indices;
    indices.buffer = 0, indices.byteOffset = indexOffset, indices.byteLength = indexBytes;
    indices.target = TINYGLTF_TARGET_ELEMENT_ARRAY_BUFFER;
    model.bufferViews.push_back(positions);
    model.bufferViews.push_back(indices);

    tinygltf::Accessor position;
    position.bufferView = int(model.bufferViews.size() - 2);
    position.componentType = TINYGLTF_COMPONENT_TYPE_FLOAT;
    position.type = TINYGLTF_TYPE_VEC3;
    position.count = data.vertexCount();
    std::vector<double> lo(3, std::numeric_limits<double>::infinity()), hi(3, -std::numeric_limits<double>::infinity());
    for (size_t i = 0; i < data.vertices.size(); ++i) {
      lo[i % 3] = std::min(lo[i % 3], double(data.vertices[i]));
      hi[i % 3] = std::max(hi[i % 3], double(data.vertices[i]));
    }
    position.minValues = lo, position.maxValues = hi;
    tinygltf::Accessor index;
    index.bufferView = int(model.bufferViews.size() - 1);
    index.componentType = TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT;
    index.type = TINYGLTF_TYPE_SCALAR;
    index.count = data.indices.size();
    model.accessors.push_back(position);
    model.accessors.push_back(index);

    tinygltf::Material material;
    material.name = scene.groupNames[g];
    material.pbrMetallicRoughness.baseColorFactor = colourOf(scene.groupNames[g]);
    material.pbrMetallicRoughness.metallicFactor = 0.0;
    model.materials.push_back(material);

    tinygltf::Primitive primitive;
    primitive.attributes["POSITION"] = int(model.accessors.size() - 2);
    primitive.indices = int(model.accessors.size() - 1);
    primitive.material = int(model.materials.size() - 1);
    primitive.mode = TINYGLTF_MODE_TRIANGLES;
    mesh.primitives.push_back(primitive);
  }
  model.buffers.push_back(buffer);
  model.meshes.push_back(mesh);
  tinygltf::Node node;
  node.mesh = 0;
  node.name = scene.name;
  model.nodes.push_back(node);
  tinygltf::Scene gltfScene;
  gltfScene.nodes = {0};
  model.scenes.push_back(gltfScene);
  model.defaultScene = 0;
  tinygltf::TinyGLTF writer;
  if (!writer.WriteGltfSceneToFile(&model, path, true, true, !binary, binary))
    throw std::runtime_error("cannot write '" + path + "'");
}

}  // namespace

void writeStackScene(const StackScene& scene, const std::string& path) {
  const std::string extension = path.substr(path.find_last_of('.') + 1);
  if (extension == "obj") writeObj(scene, path);
  else if (extension == "gltf") writeGltf(scene, path, false);
  else if (extension == "glb") writeGltf(scene, path, true);
  else throw std::runtime_error("cannot write '" + path + "': use .obj, .gltf or .glb");
}

}  // namespace obvh::tools
