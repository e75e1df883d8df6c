// rtcIntersect1 and rtcOccluded1 through obvh and Debian's Embree on the same scenes and rays.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "crossval_harness.h"
#include "stack_generator.h"
#include "test_scenes.h"

namespace obvh::test {
namespace {

constexpr size_t kRandomRays = 100000;
constexpr int kGridSide = 320;  // 102400 coherent rays

TEST(CrossvalIntersect, RandomTriangleSoup) {
  const SceneData scene = single("soup", randomTriangleSoup(20000, 1));
  expectNoMismatch("soup intersect", crossvalIntersect1(scene, mixedRays(scene, kRandomRays, kGridSide, 2)));
  expectNoMismatch("soup occluded", crossvalOccluded1(scene, mixedRays(scene, kRandomRays / 4, kGridSide / 2, 3)));
}

TEST(CrossvalIntersect, ClosedIcosphereSharedEdgesAndVertices) {
  const float center[3] = {0.1f, -0.2f, 0.3f};
  const SceneData scene = single("icosphere", icosphere(4, 1.f, center));
  expectNoMismatch("icosphere edges", crossvalIntersect1(scene, raysThroughEdgesAndVertices(scene.meshes[0], kRandomRays, 4)));
  expectNoMismatch("icosphere mixed", crossvalIntersect1(scene, mixedRays(scene, kRandomRays, kGridSide, 5)));
}

TEST(CrossvalIntersect, ClosedIcosphereRobustFlag) {
  const float center[3] = {0.f, 0.f, 0.f};
  const SceneData scene = single("icosphere", icosphere(3, 2.f, center));
  expectNoMismatch("icosphere robust edges",
                   crossvalIntersect1(scene, raysThroughEdgesAndVertices(scene.meshes[0], kRandomRays, 6),
                                      RTC_SCENE_FLAG_ROBUST));
}

TEST(CrossvalIntersect, BoxesOfTrianglesAndQuads) {
  SceneData scene;
  scene.name = "boxes";
  for (int i = 0; i < 27; ++i) {
    const float lo[3] = {float(i % 3) * 1.5f, float((i / 3) % 3) * 1.5f, float(i / 9) * 1.5f};
    const float hi[3] = {lo[0] + 1.f, lo[1] + 1.f + 0.1f * float(i % 4), lo[2] + 1.f};
    scene.meshes.push_back(box(lo, hi, i % 2 == 0));
  }
  expectNoMismatch("boxes mixed", crossvalIntersect1(scene, mixedRays(scene, kRandomRays, kGridSide, 7)));
  expectNoMismatch("boxes quad edges", crossvalIntersect1(scene, raysThroughEdgesAndVertices(scene.meshes[0], kRandomRays / 2, 8)));
}

// Grid meshes (RTC_GEOMETRY_TYPE_GRID): hits report the grid's primID and (u, v) across the grid;
// the rays through cell edges and vertices test the cells' shared edges, as for quad meshes.
TEST(CrossvalIntersect, GridMeshes) {
  SceneData scene = single("grids", gridPatches(40, 0.4f, 61));
  MeshData tilted = gridPatches(23, 0.f, 62);
  const float offset[3] = {0.2f, -0.3f, 0.25f};
  transformMesh(tilted, 0.7f, offset);
  for (size_t i = 0; i < tilted.vertices.size(); i += 3) std::swap(tilted.vertices[i + 1], tilted.vertices[i + 2]);
  scene.meshes.push_back(tilted);
  const std::vector<RTCRay> edges = raysThroughEdgesAndVertices(gridCellsAsQuads(scene.meshes[0]), kRandomRays / 2, 63);
  expectNoMismatch("grids mixed", crossvalIntersect1(scene, mixedRays(scene, kRandomRays, kGridSide, 64)));
  expectNoMismatch("grids edges", crossvalIntersect1(scene, edges));
  expectNoMismatch("grids edges robust", crossvalIntersect1(scene, edges, RTC_SCENE_FLAG_ROBUST));
  expectNoMismatch("grids occluded", crossvalOccluded1(scene, mixedRays(scene, kRandomRays / 4, kGridSide / 2, 65)));
}

// Motion blur (deformation): meshes of two, four and three time steps beside a still one, the grid
// mesh there only in [0.2, 0.7] of the shutter; rays at random times.
TEST(CrossvalIntersect, MotionBlurredMeshes) {
  SceneData scene;
  scene.name = "motion blur";
  scene.meshes.push_back(moving(randomTriangleSoup(5000, 71), 2, 72));
  scene.meshes.push_back(moving(quadGrid(20, 0.3f, 73), 4, 74));
  MeshData grids = moving(gridPatches(20, 0.3f, 75), 3, 76);
  grids.timeStart = 0.2f, grids.timeEnd = 0.7f;
  scene.meshes.push_back(grids);
  const float center[3] = {0.5f, 0.5f, 0.5f};
  scene.meshes.push_back(icosphere(3, 0.2f, center));
  std::vector<RTCRay> rays = mixedRays(scene, kRandomRays, kGridSide, 77);
  assignRandomTimes(rays, 78);
  expectNoMismatch("motion blur mixed", crossvalIntersect1(scene, rays));
  expectNoMismatch("motion blur robust", crossvalIntersect1(scene, rays, RTC_SCENE_FLAG_ROBUST));
  std::vector<RTCRay> shadows = mixedRays(scene, kRandomRays / 4, kGridSide / 2, 79);
  assignRandomTimes(shadows, 80);
  expectNoMismatch("motion blur occluded", crossvalOccluded1(scene, shadows));
}

// Every axis-aligned layout against Embree (the other tests use the default, bvh8 on AVX2 CPUs):
// the binary reference, four-wide, and leaves of several blocks with padded lanes.
class CrossvalAabbLayouts : public ::testing::TestWithParam<const char*> {};

TEST_P(CrossvalAabbLayouts, MatchEmbree) {
  const LoadedLibraries& libs = libraries();
  const ObvhDevice device(GetParam());
  ASSERT_NE(device.get(), nullptr);
  const float center[3] = {0.f, 0.f, 0.f};
  SceneData scene = single("icosphere+soup+quads", icosphere(4, 1.f, center));
  scene.meshes.push_back(randomTriangleSoup(10000, 19));
  scene.meshes.push_back(quadGrid(30, 0.3f, 24));
  scene.meshes.push_back(gridPatches(20, 0.3f, 25));
  tools::CommittedScene reference(*libs.embree, libs.embreeDevice, scene);
  tools::CommittedScene candidate(*libs.obvh, device.get(), scene);
  expectNoMismatch(GetParam(), compareCommitted(scene, reference, candidate, mixedRays(scene, kRandomRays, kGridSide, 20)));
}

INSTANTIATE_TEST_SUITE_P(Layouts, CrossvalAabbLayouts,
                         ::testing::Values("accel=bvh2", "accel=bvh4", "accel=bvh8", "accel=bvh4,max_leaf_size=11",
                                           "accel=bvh8,max_leaf_size=7", "accel=bvh8,max_leaf_size=1",
                                           "accel=bvh8,collapse=greedy", "accel=bvh4,collapse=greedy",
                                           "accel=bvh8,child_order=fixed", "accel=bvh4,child_order=fixed"));

// Rays the application declares coherent (RTC_INTERSECT_CONTEXT_FLAG_COHERENT) take obvh's
// predicted walk on the wide layouts (the oriented ones without their check of the previous ray);
// the answers must not change: camera-like grids, random rays and rays through shared edges,
// closest and any hit, four and eight wide, axis-aligned and oriented.
TEST(CrossvalIntersect, CoherentContextMatchesEmbree) {
  const LoadedLibraries& libs = libraries();
  const float center[3] = {0.f, 0.f, 0.f};
  SceneData scene = single("icosphere+soup", icosphere(4, 1.f, center));
  scene.meshes.push_back(randomTriangleSoup(10000, 31));
  std::vector<RTCRay> rays = mixedRays(scene, kRandomRays / 2, kGridSide, 32);
  const std::vector<RTCRay> edges = raysThroughEdgesAndVertices(scene.meshes[0], kRandomRays / 2, 33);
  rays.insert(rays.end(), edges.begin(), edges.end());
  tools::CommittedScene reference(*libs.embree, libs.embreeDevice, scene);
  for (const char* config : {"accel=bvh8", "accel=bvh4", "accel=bvh8,child_order=fixed", "accel=obb"}) {
    const ObvhDevice device(config);
    ASSERT_NE(device.get(), nullptr);
    tools::CommittedScene candidate(*libs.obvh, device.get(), scene);
    const std::string name = std::string(config) + " coherent";
    expectNoMismatch(name.c_str(),
                     compareCommitted(scene, reference, candidate, rays, RTC_INTERSECT_CONTEXT_FLAG_COHERENT));
    expectNoMismatch((name + " occlusion").c_str(),
                     compareCommittedOcclusion(scene, reference, candidate, rays, RTC_INTERSECT_CONTEXT_FLAG_COHERENT));
  }
}

// Every build quality, both libraries at the same level: HIGH is obvh's spatial-split builder
// (triangles referenced from several leaves), on long slanted lines where it splits the most.
// Axis-aligned blocks with vias (many coplanar faces) plus a random soup.
SceneData viasStackWithSoup(uint32_t soupSeed) {
  const tools::StackPreset* preset = tools::findStackPreset("vias-5.6k");
  const tools::StackScene stack = tools::generateStack(preset->params, preset->name);
  SceneData scene;
  scene.name = "vias stack + soup";
  scene.meshes = stack.groups;
  scene.meshes.push_back(randomTriangleSoup(3000, soupSeed));
  return scene;
}

TEST(CrossvalIntersect, EveryBuildQualityMatchesEmbree) {
  const LoadedLibraries& libs = libraries();
  const SceneData scene = viasStackWithSoup(31);
  for (RTCBuildQuality quality : {RTC_BUILD_QUALITY_LOW, RTC_BUILD_QUALITY_MEDIUM, RTC_BUILD_QUALITY_HIGH}) {
    tools::CommittedScene reference(*libs.embree, libs.embreeDevice, scene, RTC_SCENE_FLAG_NONE, quality);
    tools::CommittedScene candidate(*libs.obvh, libs.obvhDevice, scene, RTC_SCENE_FLAG_NONE, quality);
    const std::vector<RTCRay> rays = mixedRays(scene, kRandomRays, kGridSide, 40 + unsigned(quality));
    const std::string level = "quality " + std::to_string(int(quality));
    expectNoMismatch(level.c_str(), compareCommitted(scene, reference, candidate, rays));
    expectNoMismatch((level + " occlusion").c_str(), compareCommittedOcclusion(scene, reference, candidate, rays));
  }
}

// The alternative builders (builder=kmeans, builder=distance) in the default layout and in bvh4.
TEST(CrossvalIntersect, AlternativeBuildersMatchEmbree) {
  const LoadedLibraries& libs = libraries();
  const SceneData scene = viasStackWithSoup(37);
  tools::CommittedScene reference(*libs.embree, libs.embreeDevice, scene);
  const std::vector<RTCRay> rays = mixedRays(scene, kRandomRays, kGridSide, 57);
  for (const char* config : {"builder=kmeans", "builder=kmeans,kmeans_k=4,accel=bvh4", "builder=kmeans,accel=bvh2",
                             "builder=distance,distance_alpha=0.5,distance_source=0.2:0.3:0.1",
                             "builder=distance,distance_alpha=0,accel=bvh4"}) {
    const ObvhDevice device(config);
    ASSERT_NE(device.get(), nullptr) << config;
    tools::CommittedScene candidate(*libs.obvh, device.get(), scene);
    expectNoMismatch(config, compareCommitted(scene, reference, candidate, rays));
    expectNoMismatch((std::string(config) + " occlusion").c_str(), compareCommittedOcclusion(scene, reference, candidate, rays));
  }
}

// intersector=fast (Moeller-Trumbore) against Embree's default path, which uses the same test.
TEST(CrossvalIntersect, FastIntersectorMatchesEmbree) {
  const LoadedLibraries& libs = libraries();
  const ObvhDevice fast("intersector=fast");
  ASSERT_NE(fast.get(), nullptr);
  const float center[3] = {0.f, 0.f, 0.f};
  SceneData scene = single("icosphere+soup+quads", icosphere(4, 1.f, center));
  scene.meshes.push_back(randomTriangleSoup(10000, 21));
  scene.meshes.push_back(quadGrid(30, 0.3f, 22));
  tools::CommittedScene reference(*libs.embree, libs.embreeDevice, scene);
  tools::CommittedScene candidate(*libs.obvh, fast.get(), scene);
  expectNoMismatch("intersector=fast", compareCommitted(scene, reference, candidate, mixedRays(scene, kRandomRays, kGridSide, 23)));
}

TEST(CrossvalIntersect, NonPlanarQuadGrid) {
  const SceneData scene = single("quads", quadGrid(100, 0.4f, 9));
  expectNoMismatch("quad grid mixed", crossvalIntersect1(scene, mixedRays(scene, kRandomRays, kGridSide, 10)));
  expectNoMismatch("quad grid edges", crossvalIntersect1(scene, raysThroughEdgesAndVertices(scene.meshes[0], kRandomRays, 11)));
}

TEST(CrossvalIntersect, TriangleFanAroundOneVertex) {
  const SceneData scene = single("fan", triangleFan(64));
  expectNoMismatch("fan edges", crossvalIntersect1(scene, raysThroughEdgesAndVertices(scene.meshes[0], kRandomRays, 12)));
}

TEST(CrossvalIntersect, ManyGeometriesWithMasksAndDisabled) {
  SceneData scene;
  scene.name = "masked";
  for (int g = 0; g < 12; ++g) {
    MeshData mesh = randomTriangleSoup(1500, 100 + g);
    mesh.mask = 1u << (g % 3);
    mesh.enabled = g % 5 != 4;
    scene.meshes.push_back(std::move(mesh));
  }
  std::vector<RTCRay> rays = mixedRays(scene, kRandomRays, kGridSide, 13);
  assignMasks(rays, 14);
  expectNoMismatch("masked+disabled intersect", crossvalIntersect1(scene, rays));
  rays.resize(50000);
  expectNoMismatch("masked+disabled occluded", crossvalOccluded1(scene, rays));
}

// RTC_BUILD_QUALITY_REFIT: both libraries keep their trees and refit them after each vertex update.
TEST(CrossvalIntersect, RefitAfterVertexAnimation) {
  SceneData scene;
  scene.name = "refit";
  scene.meshes.push_back(randomTriangleSoup(5000, 25));
  scene.meshes.push_back(quadGrid(40, 0.2f, 26));
  const LoadedLibraries& libs = libraries();
  tools::CommittedScene reference(*libs.embree, libs.embreeDevice, scene);
  tools::CommittedScene candidate(*libs.obvh, libs.obvhDevice, scene);
  for (unsigned id = 0; id < 2; ++id) {
    libs.embree->rtcSetGeometryBuildQuality(reference.geometry(id), RTC_BUILD_QUALITY_REFIT);
    libs.obvh->rtcSetGeometryBuildQuality(candidate.geometry(id), RTC_BUILD_QUALITY_REFIT);
  }
  reference.recommit(scene);
  candidate.recommit(scene);
  for (int frame = 1; frame <= 3; ++frame) {
    for (MeshData& mesh : scene.meshes)
      for (size_t i = 0; i + 2 < mesh.vertices.size(); i += 3)
        mesh.vertices[i + 2] += 0.1f * std::sin(5.f * mesh.vertices[i] + float(frame));
    reference.recommit(scene);
    candidate.recommit(scene);
    expectNoMismatch("refit frame", compareCommitted(scene, reference, candidate, mixedRays(scene, kRandomRays / 4, kGridSide, 27 + frame)));
  }
  EXPECT_EQ(libs.obvh->rtcGetDeviceError(libs.obvhDevice), RTC_ERROR_NONE);
}

TEST(CrossvalIntersect, UpdatedAndRecommittedGeometry) {
  SceneData scene;
  scene.name = "updated";
  scene.meshes.push_back(randomTriangleSoup(5000, 15));
  scene.meshes.push_back(quadGrid(40, 0.2f, 16));
  const LoadedLibraries& libs = libraries();
  tools::CommittedScene reference(*libs.embree, libs.embreeDevice, scene);
  tools::CommittedScene candidate(*libs.obvh, libs.obvhDevice, scene);

  // Move the soup, disable the grid, change a mask: both libraries must see the new state.
  const float offset[3] = {0.3f, -0.2f, 0.1f};
  transformMesh(scene.meshes[0], 0.8f, offset);
  scene.meshes[1].enabled = false;
  scene.meshes[0].mask = 0x2u;
  reference.recommit(scene);
  candidate.recommit(scene);

  std::vector<RTCRay> rays = mixedRays(scene, kRandomRays, kGridSide, 17);
  assignMasks(rays, 18);
  expectNoMismatch("updated+recommitted", compareCommitted(scene, reference, candidate, rays));
  EXPECT_EQ(libs.obvh->rtcGetDeviceError(libs.obvhDevice), RTC_ERROR_NONE);
}

// Semiconductor stacks: long thin slanted boxes, coplanar faces of neighbouring solids, vias.
TEST(CrossvalIntersect, SmallStackPresets) {
  for (const char* name : {"small-1.5k", "vias-5.6k", "stepped-6.6k", "mixed-6.9k"}) {
    const tools::StackPreset* preset = tools::findStackPreset(name);
    ASSERT_NE(preset, nullptr) << name;
    const SceneData scene = tools::generateStack(preset->params, name).asScene();
    expectNoMismatch(name, crossvalIntersect1(scene, mixedRays(scene, kRandomRays / 2, kGridSide / 2, 13)));
    expectNoMismatch(name, crossvalOccluded1(scene, mixedRays(scene, kRandomRays / 4, kGridSide / 4, 14)));
  }
}

}  // namespace
}  // namespace obvh::test
