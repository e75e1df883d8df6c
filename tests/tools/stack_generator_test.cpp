// The stack generator: preset triangle counts, closed solids, and files that read back.
#include <tiny_gltf.h>
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <stdexcept>
#include <utility>

#include "mesh_loader.h"
#include "scene_writer.h"
#include "stack_generator.h"

namespace obvh::tools {
namespace {

TEST(StackGenerator, PresetsReproduceThePublishedTriangleCountsWithinFivePercent) {
  const size_t published[] = {42252, 1548, 5616, 515824, 6604, 6912, 653544};
  ASSERT_EQ(stackPresets().size(), 7u);
  for (size_t i = 0; i < 7; ++i) {
    const StackPreset& preset = stackPresets()[i];
    EXPECT_EQ(preset.params.targetTriangles, published[i]) << preset.name;
    const double count = double(generateStack(preset.params, preset.name).triangleCount());
    EXPECT_LE(std::fabs(count - double(published[i])), 0.05 * double(published[i])) << preset.name << ": " << count;
  }
}

TEST(StackGenerator, EverySolidIsClosedAndNoTriangleIsDegenerate) {
  StackParams p;
  p.layers = 3, p.angles = {0.f, 30.f, 45.f}, p.viasPerLayer = 5, p.steppedProfiles = 2, p.blocks = 5;
  const StackScene scene = generateStack(p);
  ASSERT_EQ(scene.groupNames.size(), 5u);
  for (size_t g = 0; g < scene.groups.size(); ++g) {
    const MeshData& mesh = scene.groups[g];
    std::map<std::pair<uint32_t, uint32_t>, int> directedEdges;
    for (size_t f = 0; f < mesh.primitiveCount(); ++f) {
      const uint32_t* tri = &mesh.indices[3 * f];
      for (int c = 0; c < 3; ++c) ++directedEdges[{tri[c], tri[(c + 1) % 3]}];
      float e[2][3];
      for (int k = 0; k < 3; ++k) {
        e[0][k] = mesh.vertices[3 * tri[1] + k] - mesh.vertices[3 * tri[0] + k];
        e[1][k] = mesh.vertices[3 * tri[2] + k] - mesh.vertices[3 * tri[0] + k];
      }
      const float n[3] = {e[0][1] * e[1][2] - e[0][2] * e[1][1], e[0][2] * e[1][0] - e[0][0] * e[1][2],
                          e[0][0] * e[1][1] - e[0][1] * e[1][0]};
      EXPECT_GT(n[0] * n[0] + n[1] * n[1] + n[2] * n[2], 0.f) << scene.groupNames[g] << " triangle " << f;
    }
    // Closed and consistently oriented: every directed edge once, and its reverse once.
    for (const auto& [edge, count] : directedEdges) {
      EXPECT_EQ(count, 1) << scene.groupNames[g];
      EXPECT_EQ(directedEdges.count({edge.second, edge.first}), 1u) << scene.groupNames[g];
    }
  }
}

TEST(StackGenerator, WrittenFilesReadBack) {
  const StackScene scene = generateStack(findStackPreset("small-1.5k")->params, "small");
  const std::string obj = ::testing::TempDir() + "small.obj", glb = ::testing::TempDir() + "small.glb";
  writeStackScene(scene, obj);
  EXPECT_EQ(loadMesh(obj).primitiveCount(), scene.triangleCount());
  writeStackScene(scene, glb);
  tinygltf::Model model;
  tinygltf::TinyGLTF loader;
  std::string error, warning;
  ASSERT_TRUE(loader.LoadBinaryFromFile(&model, &error, &warning, glb)) << error;
  size_t indices = 0;
  for (const tinygltf::Primitive& primitive : model.meshes.at(0).primitives)
    indices += model.accessors.at(size_t(primitive.indices)).count;
  EXPECT_EQ(indices, 3 * scene.triangleCount());
  EXPECT_EQ(model.materials.size(), scene.groups.size());
  EXPECT_THROW(writeStackScene(scene, ::testing::TempDir() + "small.stl"), std::runtime_error);
  EXPECT_THROW(generateStack(StackParams{0}), std::invalid_argument);
}

}  // namespace
}  // namespace obvh::tools
