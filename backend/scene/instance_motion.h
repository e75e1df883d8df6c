// Moving instances (Embree's instance motion blur): a local-to-world transform per time step,
// blended either element by element or, for transforms given as quaternion decompositions, part
// by part with the rotation's quaternions interpolated along the sphere (as Embree does).
#pragma once

#include <vector>

#include "math/affine.h"

namespace obvh {

// Embree's RTCQuaternionDecomposition: M = T * R * S, S upper triangular (scale, skew) plus a shift,
// R the rotation of the (normalized) quaternion (r, i, j, k), T the translation.
struct QuaternionDecomposition {
  Vec3f scale{1.f, 1.f, 1.f};
  float skewXY = 0.f, skewXZ = 0.f, skewYZ = 0.f;
  Vec3f shift, translation;
  float r = 1.f, i = 0.f, j = 0.f, k = 0.f;

  // M; false when the quaternion is zero or not finite.
  bool compose(Affine3f& out) const;
};

struct InstanceMotion {
  std::vector<Affine3f> steps;                      // local to world at each time step
  std::vector<QuaternionDecomposition> quaternions;  // the same steps as decompositions, when all are
  float timeStart = 0.f, timeEnd = 1.f;

  bool moving() const { return steps.size() > 1; }
  // Local to world at `time`; false when the time lies outside [timeStart, timeEnd].
  bool at(float time, Affine3f& localToWorld) const;
  // Bounds of everything the child's box reaches over the time range.
  Box3f bounds(const Box3f& child) const;
};

}  // namespace obvh
