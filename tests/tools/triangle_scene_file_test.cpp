// Scene files as bare triangles (obvh_bench, obvh_layouts): glTF flattened into world space at its
// pose at time 0, OBJ and PLY as the mesh loader reads them, and errors that name the file.
#include <gtest/gtest.h>

#include <stdexcept>
#include <string>

#include "mesh_loader.h"
#include "render_scene.h"
#include "scene_loader.h"
#include "triangle_scene_file.h"

namespace obvh::test {
namespace {

const std::string kEngine = "/usr/share/assimp/models/glTF2/2CylinderEngine-glTF-Binary/2CylinderEngine.glb";

TEST(TriangleSceneFile, GltfBecomesTheWorldSpaceTrianglesOfItsPose) {
  const tools::SceneData flat = render::loadTriangleScene(kEngine);
  const render::RenderScene scene = render::loadGltfScene(kEngine);
  const render::ScenePose pose = render::poseAt(scene, 0.f);
  size_t triangles = 0;
  for (const render::PlacedMesh& placed : pose.meshes)
    for (const render::Primitive& primitive : scene.meshes[size_t(placed.mesh)].primitives)
      triangles += primitive.triangleCount();
  ASSERT_EQ(flat.meshes.size(), 1u);
  EXPECT_EQ(flat.meshes[0].primitiveCount(), triangles);
  EXPECT_EQ(triangles, 121496u);
  EXPECT_EQ(flat.name, "2CylinderEngine.glb");
  // The placed copies, not the meshes' own coordinates: the flattened bounds are the pose's.
  const render::Bounds expected = render::worldBounds(scene, pose);
  render::Bounds bounds;
  const std::vector<float>& v = flat.meshes[0].vertices;
  for (size_t i = 0; i < v.size(); i += 3) bounds.extend({v[i], v[i + 1], v[i + 2]});
  for (int axis = 0; axis < 3; ++axis) {
    EXPECT_FLOAT_EQ((&bounds.lower.x)[axis], (&expected.lower.x)[axis]) << axis;
    EXPECT_FLOAT_EQ((&bounds.upper.x)[axis], (&expected.upper.x)[axis]) << axis;
  }
  for (uint32_t index : flat.meshes[0].indices) ASSERT_LT(index, flat.meshes[0].vertexCount());
}

TEST(TriangleSceneFile, ObjIsReadAsTheMeshLoaderReadsIt) {
  const std::string bunny = "/usr/share/glmark2/models/bunny.obj";
  const tools::SceneData viaScene = render::loadTriangleScene(bunny);
  const tools::SceneData viaMesh = tools::loadMesh(bunny);
  ASSERT_EQ(viaScene.meshes.size(), viaMesh.meshes.size());
  EXPECT_EQ(viaScene.meshes[0].indices, viaMesh.meshes[0].indices);
  EXPECT_EQ(viaScene.meshes[0].vertices, viaMesh.meshes[0].vertices);
}

TEST(TriangleSceneFile, ErrorsNameTheFile) {
  auto errorOf = [](const std::string& path) -> std::string {
    try {
      render::loadTriangleScene(path);
    } catch (const std::runtime_error& e) {
      return e.what();
    }
    return "no error";
  };
  EXPECT_NE(errorOf("scene.stl").find("scene.stl"), std::string::npos);
  const std::string broken = "/usr/share/assimp/models/glTF2/IndexOutOfRange/IndexOutOfRange.gltf";
  const std::string error = errorOf(broken);
  EXPECT_NE(error.find("IndexOutOfRange.gltf"), std::string::npos) << error;
  EXPECT_NE(error.find("out of range"), std::string::npos) << error;
}

}  // namespace
}  // namespace obvh::test
