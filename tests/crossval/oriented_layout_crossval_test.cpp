// The oriented layouts (accel=obb, accel=hybrid, with every split rule, with clustered leaf
// frames, with frame palettes and with PCA-fitted boxes) against Embree, ray by ray, on every semiconductor-stack preset, the bunny, a closed icosphere (rays at its
// shared edges and vertices), a triangle soup and non-planar quads.
#include <gtest/gtest.h>

#include <cctype>
#include <string>

#include "crossval_harness.h"
#include "mesh_loader.h"
#include "stack_generator.h"
#include "test_scenes.h"

namespace obvh::test {
namespace {

class OrientedLayouts : public ::testing::TestWithParam<const char*> {
 protected:
  // Intersections and occlusions through a device with this test's config.
  void expectSameAnswers(const std::string& what, const SceneData& scene, const std::vector<RTCRay>& rays) {
    const LoadedLibraries& libs = libraries();
    const ObvhDevice device(GetParam());
    ASSERT_NE(device.get(), nullptr) << GetParam();
    tools::CommittedScene reference(*libs.embree, libs.embreeDevice, scene);
    tools::CommittedScene candidate(*libs.obvh, device.get(), scene);
    ASSERT_EQ(libs.obvh->rtcGetDeviceError(device.get()), RTC_ERROR_NONE);
    expectNoMismatch((what + " intersect").c_str(), compareCommitted(scene, reference, candidate, rays));
    expectNoMismatch((what + " occluded").c_str(), compareCommittedOcclusion(scene, reference, candidate, rays));
  }
};

TEST_P(OrientedLayouts, StackPresets) {
  for (const char* name : {"small-1.5k", "vias-5.6k", "stepped-6.6k", "mixed-6.9k"}) {
    const SceneData scene = tools::generateStack(tools::findStackPreset(name)->params, name).asScene();
    expectSameAnswers(name, scene, mixedRays(scene, 40000, 160, 31));
  }
}

// The large presets (up to 654k triangles) and a real mesh (the Stanford bunny from Debian's
// glmark2-data), with fewer rays each to keep the suite short.
TEST_P(OrientedLayouts, LargeStackPresetsAndBunny) {
  for (const char* name : {"diagonal-42k", "axis-516k", "mixed-654k"}) {
    const SceneData scene = tools::generateStack(tools::findStackPreset(name)->params, name).asScene();
    expectSameAnswers(name, scene, mixedRays(scene, 12000, 90, 36));
  }
  const SceneData bunny = tools::loadMesh("/usr/share/glmark2/models/bunny.obj");
  expectSameAnswers("bunny", bunny, mixedRays(bunny, 20000, 120, 37));
}

TEST_P(OrientedLayouts, ClosedMeshSoupAndQuads) {
  const float center[3] = {0.2f, 0.3f, 0.4f};
  SceneData scene = single("icosphere+soup+quads", icosphere(4, 0.5f, center));
  scene.meshes.push_back(randomTriangleSoup(5000, 32));
  scene.meshes.push_back(quadGrid(30, 0.3f, 33));
  expectSameAnswers("mixed", scene, mixedRays(scene, 40000, 160, 34));
  expectSameAnswers("icosphere edges", scene, raysThroughEdgesAndVertices(scene.meshes[0], 40000, 35));
}

INSTANTIATE_TEST_SUITE_P(Configs, OrientedLayouts,
                         ::testing::Values("accel=obb", "accel=obb,obb_split=median", "accel=obb,obb_split=midpoint",
                                           "accel=obb,obb_split=aabb", "accel=hybrid", "accel=obb,obb_clusters=64",
                                           "accel=hybrid,obb_clusters=16,obb_bins=8", "accel=obb,intersector=fast",
                                           "accel=obb,obb_width=2", "accel=hybrid,obb_width=2", "accel=obb,obb_width=4",
                                           "accel=obb,obb_palette=0", "accel=hybrid,obb_palette=2",
                                           "accel=obb,obb_palette=4,obb_width=4", "accel=hybrid,obb_fit=pca"),
                         [](const ::testing::TestParamInfo<const char*>& info) {
                           std::string name = info.param;
                           for (char& c : name)
                             if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
                           return name;
                         });

}  // namespace
}  // namespace obvh::test
