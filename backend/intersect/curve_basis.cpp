#include "intersect/curve_basis.h"

namespace obvh {

namespace {

// Rows: the Bezier control points of a segment as weights of its four control vertices, over 6.
using BasisToBezier = double[4][4];
constexpr BasisToBezier kBezierRows = {{6, 0, 0, 0}, {0, 6, 0, 0}, {0, 0, 6, 0}, {0, 0, 0, 6}};
constexpr BasisToBezier kBSplineRows = {{1, 4, 1, 0}, {0, 4, 2, 0}, {0, 2, 4, 0}, {0, 1, 4, 1}};
constexpr BasisToBezier kCatmullRomRows = {{0, 6, 0, 0}, {-1, 6, 1, 0}, {0, 1, 6, -1}, {0, 0, 6, 0}};

const BasisToBezier& rowsOf(CurveBasis basis) {
  return basis == CurveBasis::Bezier ? kBezierRows : basis == CurveBasis::BSpline ? kBSplineRows : kCatmullRomRows;
}

}  // namespace

CubicBezier bezierOf(CurveBasis basis, const ShapeVertex v[4]) {
  CubicBezier out;
  if (basis == CurveBasis::Bezier) {
    for (int k = 0; k < 4; ++k) out.p[k] = v[k];
    return out;
  }
  const BasisToBezier& weights = rowsOf(basis);
  for (int k = 0; k < 4; ++k) {
    double p[4] = {0, 0, 0, 0};
    for (int i = 0; i < 4; ++i) {
      for (int a = 0; a < 3; ++a) p[a] += weights[k][i] * double(v[i].p[a]);
      p[3] += weights[k][i] * double(v[i].r);
    }
    out.p[k] = {{float(p[0] / 6.0), float(p[1] / 6.0), float(p[2] / 6.0)}, float(p[3] / 6.0)};
  }
  return out;
}

CurveBasisWeights curveBasisWeights(CurveBasis basis, double u) {
  const double s = 1.0 - u;
  // The Bernstein polynomials at u and their derivatives.
  const double b[4] = {s * s * s, 3.0 * s * s * u, 3.0 * s * u * u, u * u * u};
  const double db[4] = {-3.0 * s * s, 3.0 * s * s - 6.0 * s * u, 6.0 * s * u - 3.0 * u * u, 3.0 * u * u};
  const double ddb[4] = {6.0 * s, 6.0 * u - 12.0 * s, 6.0 * s - 12.0 * u, 6.0 * u};
  const BasisToBezier& rows = rowsOf(basis);
  CurveBasisWeights out{};
  for (int i = 0; i < 4; ++i)
    for (int k = 0; k < 4; ++k) {
      const double weight = rows[k][i] / 6.0;
      out.w[i] += b[k] * weight, out.dw[i] += db[k] * weight, out.ddw[i] += ddb[k] * weight;
    }
  return out;
}

}  // namespace obvh
