// The ray-by-ray comparison the shape cross-validations share (spheres and flat curves in
// shape_crossval_test.cpp, round curves in round_curve_crossval_test.cpp): every ray is traced and
// occlusion-tested through both libraries, and the answers must name the same primitive with t, u,
// v and Ng within rounding. A differing answer is excused only where the test's own double-precision
// oracle says the ray grazes a silhouette, or where it crosses the joint of two segments.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "crossval_harness.h"

namespace obvh::test {

struct ShapeAnswerRules {
  // Whether the ray passes within rounding of the outline of the primitive hit names.
  std::function<bool(const RTCRay& ray, const RTCHit& hit)> grazes;
  // Whether two different answers are the two segments meeting at a joint, both right; null: never.
  std::function<bool(const RTCRayHit& embree, const RTCRayHit& obvh)> jointTie;
  float uTolerance = 1e-3f;   // absolute
  float vTolerance = 1e-6f;   // absolute
  float ngTolerance = 1e-3f;  // relative to Embree's largest Ng component
};

struct ShapeAnswerCounts {
  size_t hits[2] = {0, 0};  // Embree, obvh
  size_t grazing = 0, joints = 0, mismatched = 0, occlusionMismatched = 0;
  std::string firstMismatch;
};

ShapeAnswerCounts compareShapeAnswers(RTCScene reference, RTCScene candidate, const std::vector<RTCRay>& rays,
                                      const ShapeAnswerRules& rules);

// Prints the counts under `what` and expects at least minimumHits of Embree's and no mismatch.
void expectSameShapeAnswers(const char* what, const ShapeAnswerCounts& counts, size_t rayCount, size_t minimumHits);

}  // namespace obvh::test
