// Flat cubic curves (Embree's RTC_GEOMETRY_TYPE_FLAT_BEZIER_CURVE, _FLAT_BSPLINE_CURVE and
// _FLAT_CATMULL_ROM_CURVE) as Debian's Embree traces them, measured ray by ray on it:
// - a segment is cut into N = tessellation rate quads (the rate truncated to an integer in [1, 16],
//   default 4) between the curve's points at u = i/N; each quad spans, at both ends, the point's
//   radius to either side across the ray: along n = normalize(p'(u) x dir), so the ribbon faces
//   the ray and its quads are not shared between rays;
// - a quad (p0 + r0 n0, p1 + r1 n1, p1 - r1 n1, p0 - r0 n0) is two triangles split along its
//   (p1 + r1 n1, p0 - r0 n0) diagonal and only their side facing the ray counts (a quad folded over
//   by a sharp bend is not seen from behind);
// - a hit reports u = (i + along) / N, v = 2 across - 1 (-1 on the +n edge), Ng = p'(u) (the curve's
//   tangent, unnormalized) and is skipped when closer to the ray origin than twice the radius
//   interpolated along the quad (as flat linear curves are).
// obvh tests the quads in double precision.
#pragma once

#include "intersect/curve_basis.h"
#include "intersect/ray.h"
#include "intersect/shapes.h"

namespace obvh {

// Quads per segment for an rtcSetGeometryTessellationRate value.
int ribbonQuadCount(float tessellationRate);

// Holds every quad of the segment whatever the ray: the Bezier form's box widened by its largest
// radius, rounded outwards.
Box3f ribbonCurveBounds(CurveBasis basis, const ShapeVertex control[4]);

// The nearest hit in [ray.tnear, ray.tfar], if any; control: the segment's four vertices in its basis.
bool intersectRibbonCurve(const Ray& ray, CurveBasis basis, const ShapeVertex control[4], int quads, ShapeHit& hit);

}  // namespace obvh
