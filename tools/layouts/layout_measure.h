// Measures one BVH configuration on one scene through obvh's backend: tree shape and SAH cost,
// build time, render time of two 1 spp views, bounding-volume tests per ray and their heatmap.
#pragma once

#include <string>
#include <vector>

#include <embree3/rtcore.h>

#include "layout_configs.h"
#include "scene_data.h"

namespace obvh::tools {

struct View {
  std::string name;  // "ortho", "persp"
  int width = 0, height = 0;
  std::vector<RTCRay> rays;  // row-major pixels
};

struct ViewMeasure {
  double renderMs = 0;            // median over runs, all cores
  double volumeTestsPerRay = -1;  // -1: the layout does not count them (wide layouts)
  std::vector<float> testsPerPixel;
};

struct LayoutMeasure {
  double sahCost = 0, depthStdDev = 0;
  size_t nodeCount = 0, leafCount = 0, orientedNodeCount = 0, memoryBytes = 0;
  double buildMs = 0;
  std::vector<ViewMeasure> views;
};

LayoutMeasure measureLayout(const SceneData& scene, const LayoutConfig& config, const std::vector<View>& views,
                            int runs);

// Tests per pixel as colours on a log scale from 1 (dark blue) to 256 (white); written as PNG.
void writeHeatmap(const std::string& path, const View& view, const std::vector<float>& testsPerPixel);

}  // namespace obvh::tools
