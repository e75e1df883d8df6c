// Meshes committed to obvh through the public API, traced one ray at a time: what the numerics
// suites (which run on obvh alone) share.
#pragma once

#include <embree3/rtcore.h>

#include <limits>
#include <vector>

#include "test_scenes.h"

namespace obvh::test {

constexpr float kInf = std::numeric_limits<float>::infinity();

class ObvhScene {
 public:
  explicit ObvhScene(const std::vector<MeshData>& meshes, const char* config = nullptr);
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

RTCRay makeRay(const float org[3], const float dir[3], float tnear = 0.f, float tfar = kInf);

}  // namespace obvh::test
