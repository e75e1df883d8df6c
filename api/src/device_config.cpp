#include "device_config.h"

#include <cstdlib>
#include <sstream>

#include "api_error.h"
#include "simd/cpu_features.h"

namespace obvh::api {

AccelLayout fastestAccel() { return simd::cpuHasAvx2() ? AccelLayout::Bvh8 : AccelLayout::Bvh4; }

namespace {

std::string trim(const std::string& s) {
  const size_t b = s.find_first_not_of(" \t\n\r");
  if (b == std::string::npos) return {};
  const size_t e = s.find_last_not_of(" \t\n\r");
  return s.substr(b, e - b + 1);
}

int parseInt(const std::string& name, const std::string& value, int minValue, int maxValue) {
  char* end = nullptr;
  const long v = std::strtol(value.c_str(), &end, 10);
  if (value.empty() || *end != '\0' || v < minValue || v > maxValue)
    fail(RTC_ERROR_INVALID_ARGUMENT, "invalid value '" + value + "' for device config token '" + name + "'");
  return int(v);
}

float parseFloat(const std::string& name, const std::string& value, float minValue, float maxValue) {
  char* end = nullptr;
  const float v = std::strtof(value.c_str(), &end);
  if (value.empty() || *end != '\0' || !(v >= minValue && v <= maxValue))
    fail(RTC_ERROR_INVALID_ARGUMENT, "invalid value '" + value + "' for device config token '" + name + "'");
  return v;
}

// "x:y:z" (commas separate the config's tokens).
Vec3f parsePoint(const std::string& name, const std::string& value) {
  Vec3f p;
  size_t start = 0;
  for (int axis = 0; axis < 3; ++axis) {
    const size_t colon = value.find(':', start);
    if ((axis < 2) != (colon != std::string::npos))
      fail(RTC_ERROR_INVALID_ARGUMENT, "invalid value '" + value + "' for device config token '" + name + "' (x:y:z)");
    p[axis] = parseFloat(name, value.substr(start, colon - start), -3.4e38f, 3.4e38f);
    start = colon + 1;
  }
  return p;
}

}  // namespace

DeviceConfig parseDeviceConfig(const std::string& text) {
  DeviceConfig config;
  std::stringstream stream(text);
  std::string token;
  while (std::getline(stream, token, ',')) {
    token = trim(token);
    if (token.empty()) continue;
    const size_t eq = token.find('=');
    const std::string name = trim(token.substr(0, eq));
    const std::string value = eq == std::string::npos ? std::string() : trim(token.substr(eq + 1));
    if (name == "threads") {
      config.threads = parseInt(name, value, 0, 4096);
    } else if (name == "verbose") {
      config.verbose = parseInt(name, value, 0, 100);
    } else if (name == "accel") {
      // Embree's own accel values name its internal structures (e.g. "bvh4.triangle4"); those
      // are ignored as Embree ignores what it does not know. obvh's layouts are plain names.
      if (value == "bvh2") {
        config.accel = AccelLayout::Bvh2;
      } else if (value == "bvh4") {
        config.accel = AccelLayout::Bvh4;
      } else if (value == "obb") {
        config.accel = AccelLayout::Obb;
      } else if (value == "hybrid") {
        config.accel = AccelLayout::Hybrid;
      } else if (value == "bvh8") {
        config.accel = AccelLayout::Bvh8;
      } else if (value == "default") {
        config.accel = fastestAccel();
      } else if (value.find('.') == std::string::npos) {
        fail(RTC_ERROR_INVALID_ARGUMENT, "unknown accel '" + value + "' (available: bvh2, bvh4, bvh8, obb, hybrid)");
      }
    } else if (name == "obb_split") {
      if (value == "sah") config.obbSplit = ObbSplit::Sah;
      else if (value == "median") config.obbSplit = ObbSplit::Median;
      else if (value == "midpoint") config.obbSplit = ObbSplit::Midpoint;
      else if (value == "aabb") config.obbSplit = ObbSplit::AabbSah;
      else fail(RTC_ERROR_INVALID_ARGUMENT, "unknown obb_split '" + value + "' (available: sah, median, midpoint, aabb)");
    } else if (name == "obb_fit") {
      if (value == "dito14" || value == "default") config.obbFit = ObbFit::Dito14;
      else if (value == "pca") config.obbFit = ObbFit::Pca;
      else fail(RTC_ERROR_INVALID_ARGUMENT, "unknown obb_fit '" + value + "' (available: dito14, pca, default)");
    } else if (name == "obb_bins") {
      config.obbBins = parseInt(name, value, 2, 1024);
    } else if (name == "obb_width") {
      if (value == "2") config.obbWidth = 2;
      else if (value == "4") config.obbWidth = 4;
      else if (value == "8" && fastestOrientedWidth() == 8) config.obbWidth = 8;
      else if (value == "8") fail(RTC_ERROR_INVALID_ARGUMENT, "obb_width=8 needs a CPU with AVX2");
      else fail(RTC_ERROR_INVALID_ARGUMENT, "invalid obb_width '" + value + "' (2, 4 or 8)");
    } else if (name == "obb_clusters") {
      config.obbClusters = parseInt(name, value, 0, 1 << 20);
    } else if (name == "obb_palette") {
      config.obbPalette = parseInt(name, value, 0, kMaxPaletteFrames);
    } else if (name == "obb_packets") {
      if (value == "on" || value == "default") config.obbPackets = true;
      else if (value == "off") config.obbPackets = false;
      else fail(RTC_ERROR_INVALID_ARGUMENT, "invalid value '" + value + "' for obb_packets (on, off or default)");
    } else if (name == "obb_cost") {
      config.obbTestCost = float(parseInt(name, value, 1, 100)) / 10.f;
    } else if (name == "intersector") {
      if (value == "watertight") {
        config.intersector = IntersectorMode::Watertight;
      } else if (value == "fast") {
        config.intersector = IntersectorMode::Fast;
      } else {
        fail(RTC_ERROR_INVALID_ARGUMENT, "unknown intersector '" + value + "' (available: watertight, fast)");
      }
    } else if (name == "child_order") {
      if (value == "near_to_far" || value == "default") config.childOrder = ChildOrder::NearToFar;
      else if (value == "fixed") config.childOrder = ChildOrder::Fixed;
      else fail(RTC_ERROR_INVALID_ARGUMENT, "unknown child_order '" + value + "' (available: near_to_far, fixed, default)");
    } else if (name == "ray_mask") {
      if (value == "on") config.rayMasks = true;
      else if (value == "off") config.rayMasks = false;
      else fail(RTC_ERROR_INVALID_ARGUMENT, "invalid value '" + value + "' for ray_mask (on or off)");
    } else if (name == "collapse") {
      if (value == "greedy") config.collapse = WideCollapse::Greedy;
      else if (value == "sah" || value == "default") config.collapse = WideCollapse::SahOptimal;
      else fail(RTC_ERROR_INVALID_ARGUMENT, "unknown collapse '" + value + "' (available: greedy, sah, default)");
    } else if (name == "spatial_budget") {
      config.spatialBudget = float(parseInt(name, value, 0, 400)) / 100.f;
    } else if (name == "traversal_cost") {
      config.traversalCost = parseFloat(name, value, 1e-3f, 1e3f);
    } else if (name == "intersection_cost") {
      config.intersectionCost = parseFloat(name, value, 1e-3f, 1e3f);
    } else if (name == "builder") {
      if (value == "sah") config.builder = TreeBuilder::Sah;
      else if (value == "kmeans") config.builder = TreeBuilder::KMeans;
      else if (value == "distance") config.builder = TreeBuilder::Distance;
      else fail(RTC_ERROR_INVALID_ARGUMENT, "unknown builder '" + value + "' (available: sah, kmeans, distance)");
    } else if (name == "kmeans_k") {
      config.kmeansArity = parseInt(name, value, 2, 8);
    } else if (name == "distance_alpha") {
      config.distanceAlpha = parseFloat(name, value, 0.f, 1.f);
    } else if (name == "distance_source") {
      config.distanceSource = parsePoint(name, value);
    } else if (name == "build_bins") {
      config.buildBins = parseInt(name, value, 2, 256);
    } else if (name == "max_leaf_size") {
      config.maxLeafSize = parseInt(name, value, 1, 64);
    }
  }
  return config;
}

std::string effectiveConfigString(const char* config) {
  std::string text = config ? config : "";
  if (const char* env = std::getenv("OBVH_CONFIG")) {
    if (!text.empty()) text += ",";
    text += env;
  }
  return text;
}

}  // namespace obvh::api
