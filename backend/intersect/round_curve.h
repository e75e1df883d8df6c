// Round cubic curves (Embree's RTC_GEOMETRY_TYPE_ROUND_BEZIER_CURVE, _ROUND_BSPLINE_CURVE and
// _ROUND_CATMULL_ROM_CURVE), with the conventions measured on Debian's Embree:
// - the surface is swept by circles of the interpolated radius r(u) centred on the curve p(u), each
//   in the plane perpendicular to the tangent p'(u); its ends are open (no caps);
// - a hit reports u (the segment's own curve parameter), v = 0 and
//   Ng = |p'(u)|^2 (hit - p(u)) / r(u) - r'(u) p'(u), unnormalized as Embree returns it;
// - rays starting inside the tube see its wall; no self-intersection rule.
// Every basis is turned into Bezier control points (exact in double) and intersected in double
// precision: the curve is cut in halves while the ray can meet a piece's bounds, and each remaining
// piece's hits are bracketed along the ray and polished with Newton's method.
#pragma once

#include "intersect/curve_basis.h"
#include "intersect/ray.h"
#include "math/vec3.h"

namespace obvh {

// Holds the whole tube: the control points' box widened by the largest radius (the curve and its
// radius stay inside their control points' convex hull).
Box3f roundCurveBounds(const CubicBezier& curve);

// The nearest hit in [ray.tnear, ray.tfar], if any.
bool intersectRoundCurve(const Ray& ray, const CubicBezier& curve, ShapeHit& hit);

}  // namespace obvh
