// Meshes committed to obvh through the public API, traced one ray at a time: what the numerics
// suites (which run on obvh alone) share.
#pragma once

#include <embree3/rtcore.h>

#include <gtest/gtest.h>

#include <limits>
#include <string>
#include <vector>

#include "test_scenes.h"

namespace obvh::test {

constexpr float kInf = std::numeric_limits<float>::infinity();

class ObvhScene {
 public:
  explicit ObvhScene(const std::vector<MeshData>& meshes, const char* config = nullptr,
                     RTCSceneFlags flags = RTC_SCENE_FLAG_NONE);
  ~ObvhScene();
  ObvhScene(const ObvhScene&) = delete;
  ObvhScene& operator=(const ObvhScene&) = delete;

  // The hit record after rtcIntersect1 (geomID RTC_INVALID_GEOMETRY_ID on a miss).
  RTCRayHit intersect(const RTCRay& ray) const;
  bool occluded(const RTCRay& ray) const;
  RTCDevice device() const { return device_; }

 private:
  RTCDevice device_;
  RTCScene scene_;
  std::vector<MeshData> meshes_;  // shared buffers point into these
};

// A way of running obvh that the hard cases are repeated under.
struct ObvhMode {
  const char* name;
  const char* config;
  RTCSceneFlags flags;
};
// Every mode: watertight (default), RTC_SCENE_FLAG_ROBUST, the fast intersector, the binary
// layout, the oriented layouts (obb, hybrid, obb with clustered leaf frames).
extern const ObvhMode kEveryMode[11];
// The modes that promise watertightness (the fast intersector does not; the accuracy study measures it).
extern const ObvhMode kWatertightModes[10];
std::string modeName(const ::testing::TestParamInfo<ObvhMode>& info);
void PrintTo(const ObvhMode& mode, std::ostream* os);

RTCRay makeRay(const float org[3], const float dir[3], float tnear = 0.f, float tfar = kInf);

}  // namespace obvh::test
