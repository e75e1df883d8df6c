// Moeller-Trumbore ray/triangle test (the "fast" intersector), formulated as Embree's fast path:
// edges e1 = v0 - v1, e2 = v2 - v0, normal cross(e2, e1). Single precision throughout; rays through
// shared edges can slip between triangles, which is the accuracy the watertight test buys back.
#pragma once

#include <cmath>

#include "intersect/ray.h"
#include "intersect/watertight_triangle.h"

namespace obvh {

inline bool intersectMoeller(const Ray& ray, const Vec3f& v0, const Vec3f& v1, const Vec3f& v2, TriangleHit& out) {
  const Vec3f e1 = v0 - v1, e2 = v2 - v0;
  const Vec3f Ng = cross(e2, e1);
  const Vec3f C = v0 - ray.org;
  const Vec3f R = cross(C, ray.dir);
  const float den = dot(Ng, ray.dir);
  const float absDen = std::fabs(den);
  const float sgn = den < 0.f ? -1.f : 1.f;
  const float U = dot(R, e2) * sgn;
  const float V = dot(R, e1) * sgn;
  if (!(U >= 0.f && V >= 0.f && U + V <= absDen) || den == 0.f) return false;
  const float T = dot(Ng, C) * sgn;
  if (!(T > absDen * ray.tnear && T <= absDen * ray.tfar)) return false;
  const float rcp = 1.f / absDen;
  out = {T * rcp, U * rcp, V * rcp};
  return true;
}

}  // namespace obvh
