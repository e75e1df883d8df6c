// The bench's memory row (scene_memory.h): what each library reports holding for a committed scene
// counts its acceleration structure, not only the geometry buffers, and grows with the scene.
#include <gtest/gtest.h>

#include <memory>
#include <string>

#include "procedural_meshes.h"
#include "rtc_library.h"
#include "scene_memory.h"

namespace {

using namespace obvh::tools;

SceneData soup(size_t triangles) {
  SceneData scene;
  scene.name = "soup";
  scene.meshes.push_back(randomTriangleSoup(triangles, 7u));
  return scene;
}

// The bytes of the vertex and index buffers the scene's commit allocates (rtcSetNewGeometryBuffer).
double bufferMegabytes(const SceneData& scene) {
  double bytes = 0;
  for (const MeshData& mesh : scene.meshes) bytes += double(mesh.vertices.size() + mesh.indices.size()) * 4.0;
  return bytes / (1024.0 * 1024.0);
}

void expectStructureCounted(const std::string& path, const char* label) {
  std::string error;
  std::unique_ptr<RtcLibrary> lib = RtcLibrary::open(path, label, error);
  ASSERT_TRUE(lib) << error;
  const SceneData small = soup(20000), large = soup(80000);
  const SceneMemory smallMemory = measureSceneMemory(*lib, "threads=1", small, RTC_BUILD_QUALITY_MEDIUM);
  const SceneMemory largeMemory = measureSceneMemory(*lib, "threads=1", large, RTC_BUILD_QUALITY_MEDIUM);
  EXPECT_GT(smallMemory.heldMegabytes, 1.5 * bufferMegabytes(small)) << label;
  EXPECT_GT(largeMemory.heldMegabytes, 1.5 * bufferMegabytes(large)) << label;
  EXPECT_GT(largeMemory.heldMegabytes, 3.0 * smallMemory.heldMegabytes) << label;
}

TEST(SceneMemory, ObvhCountsItsStructureAndGrowsWithTheScene) { expectStructureCounted(obvhDropInPath(), "obvh"); }

TEST(SceneMemory, EmbreeCountsItsStructureAndGrowsWithTheScene) {
  expectStructureCounted(referenceEmbreePath(), "embree");
}

}  // namespace
