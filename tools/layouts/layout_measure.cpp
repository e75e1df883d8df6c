#include "layout_measure.h"

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

SceneDesc describe(const SceneData& scene) {
  SceneDesc desc;
  for (size_t g = 0; g < scene.meshes.size(); ++g) desc.meshes.push_back(backendMeshDesc(scene.meshes[g], uint32_t(g)));
  desc.geometryIdLimit = uint32_t(scene.meshes.size());
  return desc;
}

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
  const SceneDesc desc = describe(scene);
  LayoutMeasure m;
  std::vector<double> buildTimes;
  SceneAccel accel;
  for (int r = 0; r < runs; ++r) {
    accel = SceneAccel{};
    buildTimes.push_back(millisecondsOf([&] { accel.build(desc, config.options); }));
  }
  m.buildMs = median(buildTimes);
  const LayoutMetrics metrics = accel.triangleLayoutMetrics();
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
  // Piecewise-linear ramp: dark blue, blue, red, yellow, white.
  static const float ramp[5][3] = {{0.f, 0.f, 0.15f}, {0.1f, 0.2f, 0.9f}, {0.9f, 0.1f, 0.1f}, {1.f, 0.9f, 0.1f}, {1.f, 1.f, 1.f}};
  std::vector<float> rgb(testsPerPixel.size() * 3);
  for (size_t i = 0; i < testsPerPixel.size(); ++i) {
    const float x = std::clamp(std::log(std::max(testsPerPixel[i], 1.f)) / std::log(256.f), 0.f, 1.f) * 4.f;
    const int k = std::min(int(x), 3);
    const float f = x - float(k);
    for (int c = 0; c < 3; ++c) rgb[3 * i + c] = ramp[k][c] * (1.f - f) + ramp[k + 1][c] * f;
  }
  writeImage(path, view.width, view.height, rgb);
}

}  // namespace obvh::tools
