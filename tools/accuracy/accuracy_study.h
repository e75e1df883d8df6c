// The accuracy study: hard numerical cases traced through any Embree-compatible library and mode,
// judged in double precision. Shared by the bench tool's accuracy report and the numerics suite.
#pragma once

#include <embree3/rtcore.h>

#include <cstdint>
#include <string>
#include <vector>

#include "hit_compare.h"
#include "rtc_library.h"
#include "scene_data.h"

namespace obvh::tools {

// One way of tracing: a library, its device config and the scene flags.
struct AccuracyMode {
  std::string name;
  const RtcLibrary* lib = nullptr;
  std::string config;
  RTCSceneFlags flags = RTC_SCENE_FLAG_NONE;
};

// obvh watertight (default), obvh with RTC_SCENE_FLAG_ROBUST, obvh fast, Embree default, Embree
// with RTC_SCENE_FLAG_ROBUST: the modes every report and test compares.
std::vector<AccuracyMode> standardModes(const RtcLibrary& embree, const RtcLibrary& obvh);

enum class CaseKind {
  ClosedConvex,  // rays from inside a closed convex mesh aimed at its vertices and edges: each must hit exactly once
  Grazing,       // rays at grazing angles near skinny triangles' edges, judged ray by ray
};

struct HardCase {
  std::string name;
  CaseKind kind = CaseKind::ClosedConvex;
  SceneData scene;
  std::vector<RTCRay> rays;
  std::vector<OcclusionTruth> truth;  // Grazing only: what double precision proves for each ray
};

struct CaseResult {
  std::string caseName;
  CaseKind kind = CaseKind::ClosedConvex;
  size_t rays = 0;
  size_t missed = 0;         // rays proven to hit that were answered as misses (leaks, for closed meshes)
  size_t doubleReports = 0;  // ClosedConvex: rays whose single crossing was reported by several primitives
  size_t falseHits = 0;      // hits (or occlusions) that double precision proves impossible
  double maxTErrorUlps = 0;  // largest |t - exact t| of a reported hit, in ulps of the exact t
  std::string firstMiss, firstFalseHit;  // hex-float rays, so a failure can be replayed
};

// Icosphere, cube grid and closed fan, each at the origin, translated to 1e4..1e7 and scaled to
// 1e-4 and 1e4; about raysPerCase rays each.
std::vector<HardCase> closedMeshCases(size_t raysPerCase, uint32_t seed);

// Skinny triangles (widths 1e-6..1e-3 of their length) and rays at grazing angles (1e-4..1e-1 rad)
// aimed within 1e-9..1e-4 of their long edges, on both sides.
HardCase grazingSkinnyCase(size_t triangles, size_t rays, uint32_t seed);

// Traces every ray of the case with rtcIntersect1 and rtcOccluded1 (and, for closed meshes, once
// more collecting every hit through a context filter) and judges the answers.
CaseResult runCase(const AccuracyMode& mode, const HardCase& hardCase);

}  // namespace obvh::tools
