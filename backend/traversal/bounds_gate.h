// A ray's first test in the oriented layouts: the axis-aligned box of every triangle the tree holds.
// Rays that miss a stack's box (three fifths of a perspective view of one, a third of an
// orthographic view) are answered here, before the ray is transformed into the palette's frames:
// that set-up and the oriented root node cost such a ray 27 ns, where Embree answers it in 12.
#pragma once

#include <algorithm>
#include <cmath>
#include <limits>

#include "intersect/ray.h"
#include "math/vec3.h"
#include "traversal/box_test.h"

namespace obvh {

// The box as four-lane rows; the fourth lane is unbounded so that it never decides.
struct GateBox {
  static constexpr float kInf = std::numeric_limits<float>::infinity();
  alignas(16) float lower[4];
  alignas(16) float upper[4];

  // Unbounded: passes every ray (a view made without its tree's bounds is slower, never wrong).
  GateBox() : GateBox(Box3f{Vec3f{-kInf, -kInf, -kInf}, Vec3f{kInf, kInf, kInf}}) {}
  explicit GateBox(const Box3f& box) {
    for (int axis = 0; axis < 3; ++axis) lower[axis] = box.lower[axis], upper[axis] = box.upper[axis];
    lower[3] = -kInf;
    upper[3] = kInf;
  }
};

// A distance limit moved by the slab test's rounding allowance (Ize 2013: three roundings in each
// computed distance) in the direction that keeps more: scaled up by 1 + 2 gamma(3) for t >= 0,
// towards zero by as much for t < 0. Infinities stay themselves; a NaN stays NaN, and every
// comparison with it keeps the ray.
inline float raisedLimit(float t) {
  return t * (t >= 0.f ? kConservativeFarScale : 1.f / kConservativeFarScale);
}

// False only when the slab test proves that the ray misses the box within [tnear, tfar]: the three
// axes' slabs (slabInterval, box_test.h, whose rule for rays that do not move along an axis the
// nodes' test shares) as lanes. Any NaN left (a NaN ray) fails the final comparison, so such rays
// go on to the tree, which answers them as before.
template <typename F4>
[[gnu::always_inline]] inline bool mayEnterBox(const GateBox& box, const Ray& ray) {
  // Lane by lane, not one four-float load: a caller that has just written the ray field by field
  // would stall that load (the stores cannot be forwarded to it), which cost the layout study's
  // loop, whose rays are made that way, more than the gate saved.
  const F4 org = F4::fromLanes([&](int axis) { return axis < 3 ? ray.org[axis] : 0.f; });
  const F4 inv = F4::broadcast(1.f) / F4::fromLanes([&](int axis) { return axis < 3 ? ray.dir[axis] : 1.f; });
  const SlabInterval<F4> slab = slabInterval(F4::load(box.lower), F4::load(box.upper), org, inv);
  // The largest entry as the negated smallest of the negated entries: exact, and one lane reduction.
  const float entry = std::max(0.f - minOfLanes(F4::broadcast(0.f) - slab.entry, 15), ray.tnear);
  const float exit = minOfLanes(slab.exit, 15);
  return !(entry > raisedLimit(exit) || entry > raisedLimit(ray.tfar));
}

}  // namespace obvh
