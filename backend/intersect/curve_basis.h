// The cubic bases of Embree's curves (Bezier, B-spline, Catmull-Rom): a segment's Bezier form and
// its control vertices' weights along it, shared by the round and the flat (ribbon) curves and by
// rtcInterpolate.
#pragma once

#include "intersect/shapes.h"

namespace obvh {

// Cubic Bezier control points with radii.
struct CubicBezier {
  ShapeVertex p[4];
};

enum class CurveBasis { Bezier, BSpline, CatmullRom };

// The Bezier form of the segment whose four control vertices are v (for B-splines and Catmull-Rom
// curves the segment between v[1] and v[2]).
CubicBezier bezierOf(CurveBasis basis, const ShapeVertex v[4]);

// The weights of a segment's four control vertices at u in the basis, with their first and
// second derivatives in u (for interpolating values along the segment).
struct CurveBasisWeights {
  double w[4], dw[4], ddw[4];
};
CurveBasisWeights curveBasisWeights(CurveBasis basis, double u);

}  // namespace obvh
