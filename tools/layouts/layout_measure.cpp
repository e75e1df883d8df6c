#include "layout_measure.h"

#include "heatmap.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>

#include "image_io.h"
#include "backend_mesh_desc.h"
#include "scene/scene_accel.h"
#include "trace_timing.h"

namespace obvh::tools {
namespace {

Ray backendRay(const RTCRay& r) {
  Ray ray;
  ray.org = {r.org_x, r.org_y, r.org_z};
  ray.dir = {r.dir_x, r.dir_y, r.dir_z};
  ray.tnear = r.tnear;
  ray.tfar = r.tfar;
  return ray;
}

bool countsVolumeTests(AccelLayout layout) { return layout != AccelLayout::Bvh4 && layout != AccelLayout::Bvh8; }

}  // namespace

LayoutMeasure measureLayout(const SceneData& scene, const LayoutConfig& config, const std::vector<View>& views,
                            int runs) {
  const SceneDesc desc = backendSceneDesc(scene);
  LayoutMeasure m;
  std::vector<double> buildTimes;
  SceneAccel accel;
  for (int r = 0; r < runs; ++r) {
    accel = SceneAccel{};
    buildTimes.push_back(millisecondsOf([&] { accel.build(desc, config.options); }));
  }
  m.buildMs = median(buildTimes);
  // The wide layouts release the binary tree the metrics measure unless asked to keep it: built
  // once more, keeping it, for the metrics alone (memory and build time stay the scene's own).
  const bool released =
      !config.options.keepBinaryTree && (accel.layout() == AccelLayout::Bvh4 || accel.layout() == AccelLayout::Bvh8);
  SceneAccel kept;
  if (released) {
    BuildOptions keep = config.options;
    keep.keepBinaryTree = true;
    kept.build(desc, keep);
  }
  const LayoutMetrics metrics = (released ? kept : accel).triangleLayoutMetrics();
  m.sahCost = metrics.sahCost;
  m.depthStdDev = metrics.depthStdDev;
  m.orientedNodeCount = metrics.orientedNodeCount;
  const SceneStats stats = accel.stats();
  m.nodeCount = stats.nodeCount;
  m.leafCount = stats.leafCount;
  m.memoryBytes = stats.memoryBytes;

  const QueryState state;
  for (const View& view : views) {
    ViewMeasure vm;
    std::vector<double> times;
    for (int r = 0; r < runs; ++r)
      times.push_back(millisecondsOf([&] {
        tbb::parallel_for(tbb::blocked_range<size_t>(0, view.rays.size(), 256), [&](const tbb::blocked_range<size_t>& b) {
          for (size_t i = b.begin(); i < b.end(); ++i) {
            Ray ray = backendRay(view.rays[i]);
            Hit hit;
            accel.intersect(ray, hit, state);
          }
        });
      }));
    vm.renderMs = median(times);
    if (countsVolumeTests(accel.layout())) {
      // A separate pass: counting is kept out of the timed one.
      vm.testsPerPixel.assign(view.rays.size(), 0.f);
      tbb::parallel_for(tbb::blocked_range<size_t>(0, view.rays.size(), 256), [&](const tbb::blocked_range<size_t>& b) {
        for (size_t i = b.begin(); i < b.end(); ++i) {
          Ray ray = backendRay(view.rays[i]);
          Hit hit;
          TraversalCounters counters;
          accel.intersect(ray, hit, state, &counters);
          vm.testsPerPixel[i] = float(counters.volumeTests());
        }
      });
      double total = 0;
      for (float t : vm.testsPerPixel) total += t;
      vm.volumeTestsPerRay = view.rays.empty() ? 0.0 : total / double(view.rays.size());
    }
    m.views.push_back(std::move(vm));
  }
  return m;
}

void writeHeatmap(const std::string& path, const View& view, const std::vector<float>& testsPerPixel) {
  writeHeatmap(path, view.width, view.height, testsPerPixel);
}

}  // namespace obvh::tools
