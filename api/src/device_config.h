// Parses rtcNewDevice's configuration string (Embree tokens plus obvh's own).
#pragma once

#include <string>

#include "builders/build_options.h"
#include "traversal/oriented_wide_traversal.h"

namespace obvh::api {

// The fastest layout this CPU runs: bvh8 with AVX2, else bvh4 (measured: README, performance).
AccelLayout fastestAccel();

struct DeviceConfig {
  int threads = 0;  // 0: TBB's default
  int verbose = 0;
  AccelLayout accel = fastestAccel();
  // RTC_SCENE_FLAG_ROBUST always selects the watertight test; this is the default for other scenes.
  IntersectorMode intersector = IntersectorMode::Watertight;
  ChildOrder childOrder = ChildOrder::NearToFar;  // closest-hit single rays in bvh4/bvh8
  int buildBins = 32;
  int maxLeafSize = 0;  // 0: the layout's and builder's default (defaultMaxLeafSize)
  ObbSplit obbSplit = ObbSplit::AabbSah;  // accel=obb|hybrid only; see BuildOptions
  int obbBins = 32;
  ObbFit obbFit = ObbFit::Dito14;  // obb_fit=dito14|pca
  int obbClusters = 0;
  int obbPalette = -1;  // obb_palette=K (see BuildOptions); -1: kDefaultObbPalette, or 0 with obb_clusters
  int obbWidth = fastestOrientedWidth();  // obb_width=2|4|8: the oriented layouts traced binary, four- or eight-wide
  float obbTestCost = 2.f;
  bool obbPackets = true;  // obb_packets=off: closest-hit packets through eight-wide oriented trees ray by ray
  float traversalCost = 1.f;     // SAH cost of a node visit (traversal_cost)
  float intersectionCost = 1.f;  // SAH cost of a primitive test (intersection_cost)
  TreeBuilder builder = TreeBuilder::Sah;
  int kmeansArity = 0;           // 0: the layout's width (4 for bvh4, 8 for bvh8, 2 for bvh2)
  float distanceAlpha = 0.5f;
  Vec3f distanceSource{0.f, 0.f, 0.f};
  WideCollapse collapse = WideCollapse::SahOptimal;  // collapse=greedy|sah
  float spatialBudget = 1.f;  // RTC_BUILD_QUALITY_HIGH: extra references per triangle (spatial_budget, percent)
  // ray_mask=off: ignore ray and geometry masks, for programs written against builds without masks.
  bool rayMasks = true;
};

// Tokens are "name=value" separated by commas. Like Embree, names obvh does not know are ignored;
// a known name with a value obvh cannot honour raises RTC_ERROR_INVALID_ARGUMENT (via ApiError).
DeviceConfig parseDeviceConfig(const std::string& text);

// The config string plus the OBVH_CONFIG environment variable, which applies to every device.
std::string effectiveConfigString(const char* config);

}  // namespace obvh::api
