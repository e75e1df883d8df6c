// Loads an Embree 3 compatible library (Debian's Embree or obvh's drop-in) as a table of function
// pointers, so one process can drive both: both export the same rtc* names, which is why each is
// opened with RTLD_LOCAL | RTLD_DEEPBIND instead of being linked.
#pragma once

#include <embree3/rtcore.h>
#include <obvh/traversal_statistics.h>

#include <memory>
#include <string>

namespace obvh::tools {

// Every function declared by the Embree 3 API headers.
#define OBVH_RTC_FUNCTIONS(X) \
  X(rtcNewDevice) \
  X(rtcRetainDevice) \
  X(rtcReleaseDevice) \
  X(rtcGetDeviceProperty) \
  X(rtcSetDeviceProperty) \
  X(rtcGetDeviceError) \
  X(rtcSetDeviceErrorFunction) \
  X(rtcSetDeviceMemoryMonitorFunction) \
  X(rtcNewBuffer) \
  X(rtcNewSharedBuffer) \
  X(rtcGetBufferData) \
  X(rtcRetainBuffer) \
  X(rtcReleaseBuffer) \
  X(rtcNewGeometry) \
  X(rtcRetainGeometry) \
  X(rtcReleaseGeometry) \
  X(rtcCommitGeometry) \
  X(rtcEnableGeometry) \
  X(rtcDisableGeometry) \
  X(rtcSetGeometryTimeStepCount) \
  X(rtcSetGeometryTimeRange) \
  X(rtcSetGeometryVertexAttributeCount) \
  X(rtcSetGeometryMask) \
  X(rtcSetGeometryBuildQuality) \
  X(rtcSetGeometryMaxRadiusScale) \
  X(rtcSetGeometryBuffer) \
  X(rtcSetSharedGeometryBuffer) \
  X(rtcSetNewGeometryBuffer) \
  X(rtcGetGeometryBufferData) \
  X(rtcUpdateGeometryBuffer) \
  X(rtcSetGeometryIntersectFilterFunction) \
  X(rtcSetGeometryOccludedFilterFunction) \
  X(rtcSetGeometryUserData) \
  X(rtcGetGeometryUserData) \
  X(rtcSetGeometryPointQueryFunction) \
  X(rtcSetGeometryUserPrimitiveCount) \
  X(rtcSetGeometryBoundsFunction) \
  X(rtcSetGeometryIntersectFunction) \
  X(rtcSetGeometryOccludedFunction) \
  X(rtcFilterIntersection) \
  X(rtcFilterOcclusion) \
  X(rtcSetGeometryInstancedScene) \
  X(rtcSetGeometryTransform) \
  X(rtcSetGeometryTransformQuaternion) \
  X(rtcGetGeometryTransform) \
  X(rtcSetGeometryTessellationRate) \
  X(rtcSetGeometryTopologyCount) \
  X(rtcSetGeometrySubdivisionMode) \
  X(rtcSetGeometryVertexAttributeTopology) \
  X(rtcSetGeometryDisplacementFunction) \
  X(rtcGetGeometryFirstHalfEdge) \
  X(rtcGetGeometryFace) \
  X(rtcGetGeometryNextHalfEdge) \
  X(rtcGetGeometryPreviousHalfEdge) \
  X(rtcGetGeometryOppositeHalfEdge) \
  X(rtcInterpolate) \
  X(rtcInterpolateN) \
  X(rtcNewScene) \
  X(rtcGetSceneDevice) \
  X(rtcRetainScene) \
  X(rtcReleaseScene) \
  X(rtcAttachGeometry) \
  X(rtcAttachGeometryByID) \
  X(rtcDetachGeometry) \
  X(rtcGetGeometry) \
  X(rtcGetGeometryThreadSafe) \
  X(rtcCommitScene) \
  X(rtcJoinCommitScene) \
  X(rtcSetSceneProgressMonitorFunction) \
  X(rtcSetSceneBuildQuality) \
  X(rtcSetSceneFlags) \
  X(rtcGetSceneFlags) \
  X(rtcGetSceneBounds) \
  X(rtcGetSceneLinearBounds) \
  X(rtcPointQuery) \
  X(rtcPointQuery4) \
  X(rtcPointQuery8) \
  X(rtcPointQuery16) \
  X(rtcIntersect1) \
  X(rtcIntersect4) \
  X(rtcIntersect8) \
  X(rtcIntersect16) \
  X(rtcIntersect1M) \
  X(rtcIntersect1Mp) \
  X(rtcIntersectNM) \
  X(rtcIntersectNp) \
  X(rtcOccluded1) \
  X(rtcOccluded4) \
  X(rtcOccluded8) \
  X(rtcOccluded16) \
  X(rtcOccluded1M) \
  X(rtcOccluded1Mp) \
  X(rtcOccludedNM) \
  X(rtcOccludedNp) \
  X(rtcCollide) \
  X(rtcNewBVH) \
  X(rtcBuildBVH) \
  X(rtcThreadLocalAlloc) \
  X(rtcRetainBVH) \
  X(rtcReleaseBVH)

struct RtcLibrary {
#define OBVH_DECLARE_POINTER(name) decltype(&::name) name = nullptr;
  OBVH_RTC_FUNCTIONS(OBVH_DECLARE_POINTER)
#undef OBVH_DECLARE_POINTER

  // obvh's own extensions; null when the library does not have them (Debian's Embree).
  decltype(&::obvhEnableTraversalStatistics) obvhEnableTraversalStatistics = nullptr;
  decltype(&::obvhTakeTraversalStatistics) obvhTakeTraversalStatistics = nullptr;

  std::string path;
  std::string label;  // short name for reports, e.g. "embree" or "obvh"

  RtcLibrary() = default;
  RtcLibrary(const RtcLibrary&) = delete;
  RtcLibrary& operator=(const RtcLibrary&) = delete;
  ~RtcLibrary();

  // Returns nullptr and sets error when the library or one of its symbols cannot be loaded.
  static std::unique_ptr<RtcLibrary> open(const std::string& path, const std::string& label, std::string& error);

 private:
  void* handle_ = nullptr;
};

// Where Debian installs the reference Embree, and where this build puts obvh's drop-in.
std::string referenceEmbreePath();
std::string obvhDropInPath();

}  // namespace obvh::tools
