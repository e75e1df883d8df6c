// Broken glTF files (Debian's assimp-testmodels) give an error naming the problem, never a crash
// or a rendered guess; good ones load with their cameras, animations and materials.
#include <gtest/gtest.h>

#include <fstream>
#include <stdexcept>

#include "render_fixture.h"
#include "scene_loader.h"

namespace obvh::test {
namespace {

const std::string kSamples = "/usr/share/assimp/models/glTF2/";

std::string loadError(const std::string& path) {
  try {
    render::loadRenderScene(path);
  } catch (const std::exception& e) {
    return e.what();
  }
  return "";
}

TEST(GltfLoader, BrokenSamplesAreRefusedWithTheReason) {
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"IndexOutOfRange/IndexOutOfRange.gltf", "index 255 is out of range (24 vertices)"},
      {"IndexOutOfRange/AllIndicesOutOfRange.gltf", "is out of range (24 vertices)"},
      {"MissingBin/BoxTextured.gltf", "BoxTextured0.bin"},
      {"wrongTypes/badArray.gltf", "meshes[0].primitives must be an array (it is an object)"},
      {"wrongTypes/badObject.gltf", "materials[0].pbrMetallicRoughness must be an object (it is an array)"},
      {"wrongTypes/badNumber.gltf", "materials[0].normalTexture.scale must be a number (it is a string)"},
      {"wrongTypes/badString.gltf", "scenes[0].name must be a string (it is an integer)"},
      {"wrongTypes/badUint.gltf", "baseColorTexture.index must be a non-negative integer (it is a negative integer)"},
      {"wrongTypes/badExtension.gltf", "extensions.KHR_texture_transform must be an object (it is a string)"},
      {"SchemaFailures/sceneWrongType.gltf", "scene must be a non-negative integer (it is a string)"},
      {"RecursiveNodes/RecursiveNodes.gltf", "the node hierarchy has a cycle"},
      {"BoxWithInfinites-glTF-Binary/BoxWithInfinites.glb", "non-finite vertex position"},
      {"IncorrectVertexArrays/Cube.gltf", "35 indices do not make whole triangles"},
      {"TestNoRootNode/SceneWithoutNodes.gltf", "the scene has no triangles to render"},
      {"draco/2CylinderEngine.gltf", "requires extension KHR_draco_mesh_compression"},
  };
  for (const auto& [file, reason] : cases) {
    const std::string error = loadError(kSamples + file);
    EXPECT_NE(error.find(reason), std::string::npos) << file << "\n  error: " << error;
    EXPECT_NE(error.find(file.substr(file.find('/') + 1)), std::string::npos) << "the error names the file: " << error;
  }
}

TEST(GltfLoader, MissingAndUnknownFilesAreNamed) {
  EXPECT_NE(loadError("/nonexistent/scene.glb").find("/nonexistent/scene.glb"), std::string::npos);
  EXPECT_NE(loadError("/etc/hostname").find("reads .gltf, .glb, .obj, .ply and .stl"), std::string::npos);
  const std::string truncated = std::string(OBVH_TEST_WORK_DIR) + "/truncated.glb";
  std::ofstream(truncated) << "glTF\x02";
  EXPECT_NE(loadError(truncated).find("truncated"), std::string::npos) << loadError(truncated);
}

TEST(GltfLoader, GoodSamplesLoadWhatTheyDescribe) {
  const render::RenderScene engine = render::loadRenderScene(kSamples + "2CylinderEngine-glTF-Binary/2CylinderEngine.glb");
  const render::ScenePose enginePose = render::poseAt(engine, 0.f);
  EXPECT_EQ(engine.triangleCount(), 75730u);
  EXPECT_EQ(enginePose.meshes.size(), 67u);
  EXPECT_EQ(enginePose.cameras.size(), 1u);

  const render::RenderScene cameras = render::loadRenderScene(kSamples + "cameras/Cameras.gltf");
  EXPECT_EQ(render::poseAt(cameras, 0.f).cameras.size(), 2u);

  const render::RenderScene textured = render::loadRenderScene(kSamples + "BoxTextured-glTF/BoxTextured.gltf");
  ASSERT_EQ(textured.textures.size(), 1u);
  EXPECT_GT(textured.textures[0].width, 0);

  const render::RenderScene skinned = render::loadRenderScene(kSamples + "simple_skin/simple_skin.gltf");
  ASSERT_FALSE(skinned.warnings.empty());
  EXPECT_NE(skinned.warnings[0].find("skinning is not applied"), std::string::npos);

  const render::RenderScene controller = render::loadRenderScene(webxrControllerPath());
  bool transmissive = false, blended = false;
  for (const render::Material& m : controller.materials) {
    transmissive = transmissive || m.transmission > 0.f;
    blended = blended || m.alphaMode == render::AlphaMode::Blend;
  }
  EXPECT_TRUE(transmissive);
  EXPECT_TRUE(blended);
}

TEST(GltfLoader, AnimationMovesNodesBetweenKeys) {
  const render::RenderScene scene = render::loadRenderScene(showcaseScenePath("animated"));
  EXPECT_FLOAT_EQ(scene.animationDuration(), 2.f);
  // The slider goes from x = -0.8 at t = 0 to 0.8 at t = 1: halfway at t = 0.5.
  const auto sliderX = [&](float time) {
    const render::ScenePose pose = render::poseAt(scene, time);
    for (const render::PlacedMesh& placed : pose.meshes)
      if (scene.meshes[size_t(placed.mesh)].name == "slider") return placed.toWorld(0, 3);
    return 1e9f;
  };
  EXPECT_NEAR(sliderX(0.f), -0.8f, 1e-6f);
  EXPECT_NEAR(sliderX(0.5f), 0.f, 1e-6f);
  EXPECT_NEAR(sliderX(1.f), 0.8f, 1e-6f);
  EXPECT_NEAR(sliderX(5.f), -0.8f, 1e-6f);  // clamped after the last key
}

}  // namespace
}  // namespace obvh::test
