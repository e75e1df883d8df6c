// Assembles small glTF 2.0 scenes in code (meshes, materials with the KHR material extensions,
// textures, punctual lights, cameras, node animations) and writes them through tinygltf.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace tinygltf {
class Model;
}

namespace obvh::tools {

struct GltfMaterialDesc {
  std::string name;
  std::array<double, 4> baseColor{0.8, 0.8, 0.8, 1.0};
  std::array<double, 3> emissive{0.0, 0.0, 0.0};
  std::string alphaMode = "OPAQUE";
  double alphaCutoff = 0.5;
  double transmission = 0.0, ior = 1.5, dispersion = 0.0;  // extensions written only when non-default
  int baseColorTexture = -1;  // from addTexture
};

struct TriangleList {
  std::vector<float> positions;  // x, y, z
  std::vector<float> uvs;        // empty or u, v per vertex
  std::vector<uint32_t> indices;
  // Appends a quad a, b, c, d (counter-clockwise seen from the side it faces), with uvs 0..1.
  void quad(const std::array<float, 3>& a, const std::array<float, 3>& b, const std::array<float, 3>& c,
            const std::array<float, 3>& d);
  void triangle(const std::array<float, 3>& a, const std::array<float, 3>& b, const std::array<float, 3>& c);
  // Closed box with outward-facing triangles.
  void box(const std::array<float, 3>& lower, const std::array<float, 3>& upper);
};

class GltfBuilder {
 public:
  GltfBuilder();
  ~GltfBuilder();
  int addMaterial(const GltfMaterialDesc& material);
  // RGBA8 texels, row by row; nearest filtering is not asked for, the renderer filters bilinearly.
  int addTexture(int width, int height, const std::vector<uint8_t>& rgba);
  int addMesh(const std::string& name, const TriangleList& triangles, int material);
  int addNode(const std::string& name, int mesh, const std::array<float, 3>& translation = {0, 0, 0},
              const std::array<float, 4>& rotation = {0, 0, 0, 1}, const std::array<float, 3>& scale = {1, 1, 1});
  void addChild(int parent, int child);
  // type: "point", "spot" or "directional"; placed by a new node.
  int addLight(const std::string& type, const std::array<float, 3>& colour, double intensity,
               const std::array<float, 3>& position, const std::array<float, 4>& rotation = {0, 0, 0, 1});
  // A perspective camera at `eye` looking at `target` (+Y up).
  int addCamera(const std::array<float, 3>& eye, const std::array<float, 3>& target, double yfov);
  // One channel: path "translation", "rotation" or "scale"; values 3 or 4 floats per key.
  void animate(int node, const std::string& path, const std::vector<float>& times, const std::vector<float>& values);
  // Writes .gltf (embedded buffers) or .glb; throws std::runtime_error on failure.
  void write(const std::string& path);

 private:
  int addAccessor(const void* data, size_t bytes, int componentType, int type, size_t count,
                  const std::vector<double>& lo = {}, const std::vector<double>& hi = {});
  tinygltf::Model* model_;
  std::vector<int> roots_;
};

}  // namespace obvh::tools
