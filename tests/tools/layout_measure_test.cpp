// The layout study's measurements on a small slanted stack: counts where the layout counts, the
// oriented boxes' SAH advantage on slanted lines, and a heatmap file.
#include <gtest/gtest.h>

#include <filesystem>
#include <stdexcept>

#include "layout_measure.h"
#include "ray_generation.h"
#include "stack_generator.h"

namespace obvh::tools {
namespace {

struct SmallStudy {
  SceneData scene;
  std::vector<View> views;
  SmallStudy() {
    const StackPreset& preset = *findStackPreset("small-1.5k");
    scene = generateStack(preset.params, preset.name).asScene();
    const SceneBox box{{0.f, 0.f, 0.f}, {100.f, 100.f, 20.f}};
    views = {{"ortho", 64, 36, orthographicRays(box, 64, 36)}, {"persp", 64, 36, perspectiveRays(box, 64, 36)}};
  }
};

TEST(LayoutMeasure, CountsVolumeTestsWhereTheLayoutCountsThem) {
  const SmallStudy s;
  const LayoutMeasure aabb = measureLayout(s.scene, *findLayoutConfig("aabb"), s.views, 1);
  const LayoutMeasure wide = measureLayout(s.scene, *findLayoutConfig("aabb-bvh8"), s.views, 1);
  ASSERT_EQ(aabb.views.size(), 2u);
  for (const ViewMeasure& v : aabb.views) {
    EXPECT_GE(v.volumeTestsPerRay, 1.0);  // every ray tests the root at least
    EXPECT_EQ(v.testsPerPixel.size(), 64u * 36u);
    EXPECT_GT(v.renderMs, 0.0);
  }
  for (const ViewMeasure& v : wide.views) EXPECT_EQ(v.volumeTestsPerRay, -1.0);
  EXPECT_GT(aabb.nodeCount, wide.nodeCount);
  EXPECT_GT(aabb.leafCount, 0u);
  EXPECT_GT(aabb.memoryBytes, 0u);
}

TEST(LayoutMeasure, OrientedBoxesCutSahCostAndTestsOnSlantedLines) {
  const SmallStudy s;
  const LayoutMeasure aabb = measureLayout(s.scene, *findLayoutConfig("aabb"), s.views, 1);
  const LayoutMeasure obb = measureLayout(s.scene, *findLayoutConfig("obb"), s.views, 1);
  EXPECT_EQ(aabb.orientedNodeCount, 0u);
  EXPECT_GT(obb.orientedNodeCount, 0u);
  EXPECT_LT(obb.sahCost, 0.5 * aabb.sahCost);
  EXPECT_LT(obb.views[1].volumeTestsPerRay, aabb.views[1].volumeTestsPerRay);
}

// The oriented layouts count their volume tests per pixel (the hybrid may settle on the wide
// AABB layout, which does not).
TEST(LayoutMeasure, WritesAHeatmap) {
  const SmallStudy s;
  const LayoutMeasure m = measureLayout(s.scene, *findLayoutConfig("obb"), s.views, 1);
  ASSERT_EQ(m.views[1].testsPerPixel.size(), s.views[1].rays.size());
  const std::string path = (std::filesystem::temp_directory_path() / "obvh_layout_heatmap_test.png").string();
  std::filesystem::remove(path);
  writeHeatmap(path, s.views[1], m.views[1].testsPerPixel);
  EXPECT_GT(std::filesystem::file_size(path), 100u);
  std::filesystem::remove(path);
}

TEST(LayoutMeasure, HeatmapWithoutCountsIsAnErrorNotACrash) {
  const SmallStudy s;
  const std::string path = (std::filesystem::temp_directory_path() / "obvh_layout_heatmap_empty.png").string();
  EXPECT_THROW(writeHeatmap(path, s.views[1], {}), std::invalid_argument);
  EXPECT_FALSE(std::filesystem::exists(path));
}

}  // namespace
}  // namespace obvh::tools
