// Slab test of one ray against one axis-aligned box, conservative in the sense of Ize (2013):
// the far distance is scaled up by 1 + 2*gamma(3) so that rounding never culls a box that the
// exact ray enters, which the watertight triangle test relies on.
#pragma once

#include <cmath>
#include <cstdint>

#include "intersect/ray.h"

namespace obvh {

constexpr float kUnitRoundoff = 0x1p-24f;
constexpr float gammaBound(int n) { return (float(n) * kUnitRoundoff) / (1.f - float(n) * kUnitRoundoff); }
constexpr float kConservativeFarScale = 1.f + 2.f * gammaBound(3);
// How far the wide node tests' integer form raises the exit distance, in ulps: at least the
// relative 2 * gamma(3) of Ize's scaling (kConservativeFarScale), which is under 6 ulps of any
// float, with room to spare. An integer add, where the float form multiplies.
constexpr int32_t kConservativeFarUlps = 8;

// Per-ray constants of the slab test.
struct BoxRay {
  Vec3f org;
  Vec3f invDir;
  Vec3f dir;
  bool hasZeroComponent = false;

  explicit BoxRay(const Ray& ray) : org(ray.org), dir(ray.dir) {
    for (int axis = 0; axis < 3; ++axis) {
      if (ray.dir[axis] == 0.f) hasZeroComponent = true;
      invDir[axis] = 1.f / ray.dir[axis];
    }
  }
};

// Rays with a zero direction component never move along that axis: they are inside that slab for
// all t when the origin is within [lower, upper] (inclusive) and nowhere otherwise. Handling this
// exactly keeps rays that run inside a box face consistent with the triangle test.
inline float intersectBoxWithZeroComponents(const BoxRay& r, const Box3f& box, float tnear, float tfar) {
  float tmin = tnear, tmax = std::numeric_limits<float>::infinity();
  for (int axis = 0; axis < 3; ++axis) {
    if (r.dir[axis] == 0.f) {
      if (!(r.org[axis] >= box.lower[axis] && r.org[axis] <= box.upper[axis])) return std::numeric_limits<float>::infinity();
      continue;
    }
    const float t0 = (box.lower[axis] - r.org[axis]) * r.invDir[axis];
    const float t1 = (box.upper[axis] - r.org[axis]) * r.invDir[axis];
    if (std::isnan(t0) || std::isnan(t1)) return std::numeric_limits<float>::infinity();
    tmin = std::max(tmin, std::min(t0, t1));
    tmax = std::min(tmax, std::max(t0, t1));
  }
  return tmin <= std::min(tmax * kConservativeFarScale, tfar) ? tmin : std::numeric_limits<float>::infinity();
}

// One axis' slab of several boxes at once (F: SIMD lanes, one box a lane), given the ray's origin
// and inverse direction along that axis: the distances at which the ray enters and leaves it. A ray
// that does not move along the axis (1/dir infinite) gets -inf..+inf from a slab that holds its
// origin and an empty interval from one that does not; an origin exactly on a plane makes that
// plane's distance 0 * inf = NaN, replaced by the value that leaves the slab unbounded on that side
// (-1/dir for the lower plane, 1/dir for the upper), so the ray counts as inside, as in the scalar
// test above.
template <typename F>
struct SlabInterval {
  F entry, exit;
};

template <typename F>
[[gnu::always_inline]] inline SlabInterval<F> slabInterval(F lowerPlane, F upperPlane, F o, F inv) {
  const F t0 = replaceNaN((lowerPlane - o) * inv, F::broadcast(0.f) - inv);
  const F t1 = replaceNaN((upperPlane - o) * inv, inv);
  return {min(t0, t1), max(t0, t1)};
}

// Returns the entry distance, or +inf when the box is missed within [tnear, tfar].
inline float intersectBox(const BoxRay& r, const Box3f& box, float tnear, float tfar) {
  if (r.hasZeroComponent) return intersectBoxWithZeroComponents(r, box, tnear, tfar);
  const float x0 = (box.lower.x - r.org.x) * r.invDir.x, x1 = (box.upper.x - r.org.x) * r.invDir.x;
  const float y0 = (box.lower.y - r.org.y) * r.invDir.y, y1 = (box.upper.y - r.org.y) * r.invDir.y;
  const float z0 = (box.lower.z - r.org.z) * r.invDir.z, z1 = (box.upper.z - r.org.z) * r.invDir.z;
  // A NaN anywhere (a NaN ray) makes the final comparison false, so such rays enter no box.
  const float tmin = std::max(std::max(std::min(x0, x1), std::min(y0, y1)), std::max(std::min(z0, z1), tnear));
  const float tmax = std::min(std::min(std::max(x0, x1), std::max(y0, y1)), std::max(z0, z1)) * kConservativeFarScale;
  return tmin <= std::min(tmax, tfar) ? tmin : std::numeric_limits<float>::infinity();
}

}  // namespace obvh
