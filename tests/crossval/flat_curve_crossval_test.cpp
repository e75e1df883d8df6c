// Flat cubic curves (RTC_GEOMETRY_TYPE_FLAT_BEZIER_CURVE, _FLAT_BSPLINE_CURVE,
// _FLAT_CATMULL_ROM_CURVE) through obvh and Debian's Embree: ribbons that face the ray, cut into
// as many quads a segment as the tessellation rate says. The same primitive on every ray, t, u, v
// and Ng within rounding (Embree works in float). Answers may differ only where the ray passes
// within rounding of a ribbon's outline, of the depth below which a hit is skipped (twice the
// radius), or crosses the joint of two segments; each such claim is checked here in double
// precision on the ribbon built from the curve in its own basis.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "curve_scene.h"
#include "shape_answers.h"

namespace obvh::test {
namespace {

struct Vec {
  double x, y, z;
};
Vec operator+(Vec a, Vec b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
Vec operator-(Vec a, Vec b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
Vec operator*(double s, Vec a) { return {s * a.x, s * a.y, s * a.z}; }
double dot(Vec a, Vec b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
Vec cross(Vec a, Vec b) { return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x}; }

// Where the ray crosses the plane of triangle (a, b, c): its barycentric weights and depth.
struct Crossing {
  double wa, wb, wc, t;
  bool valid;
};
Crossing crossing(Vec org, Vec dir, Vec a, Vec b, Vec c) {
  const Vec e1 = b - a, e2 = c - a, p = cross(dir, e2);
  const double det = dot(e1, p);
  if (std::fabs(det) < 1e-300) return {0, 0, 0, 0, false};
  const Vec s = org - a, q = cross(s, e1);
  const double wb = dot(s, p) / det, wc = dot(dir, q) / det;
  return {1.0 - wb - wc, wb, wc, dot(e2, q) / det, true};
}

// Whether the ray passes within rounding of where the ribbon of this segment (cut into `quads`)
// starts or stops being hit: its long edges, its two end edges, the skip depth, or a tangent
// seen end-on (where the ribbon's width direction is undefined).
bool grazesRibbon(const RTCRay& ray, int basis, const Point4* control, int quads) {
  const Vec org{ray.org_x, ray.org_y, ray.org_z}, dir{ray.dir_x, ray.dir_y, ray.dir_z};
  const double length = std::sqrt(dot(dir, dir));
  const Vec unit = (1.0 / length) * dir;
  constexpr double kNear = 1e-4;
  Vec corner[17][2];
  double radius[17];
  for (int i = 0; i <= quads; ++i) {
    const CurvePoint e = evaluateCurve(basis, control, double(i) / quads);
    const Vec p{e.p[0], e.p[1], e.p[2]}, tangent{e.dp[0], e.dp[1], e.dp[2]};
    Vec n = cross(tangent, unit);
    const double l = std::sqrt(dot(n, n));
    if (l < 1e-3 * std::sqrt(dot(tangent, tangent))) return true;
    n = (1.0 / l) * n;
    corner[i][0] = p + e.r * n, corner[i][1] = p - e.r * n;
    radius[i] = e.r;
  }
  for (int i = 0; i < quads; ++i) {
    // The quad's two triangles; for each, which of its edges lie on the ribbon's outline.
    const Vec &a = corner[i][0], &b = corner[i + 1][0], &c = corner[i + 1][1], &d = corner[i][1];
    const Crossing halves[2] = {crossing(org, dir, a, b, d), crossing(org, dir, c, d, b)};
    for (int h = 0; h < 2; ++h) {
      const Crossing& x = halves[h];
      if (!x.valid || std::min({x.wa, x.wb, x.wc}) < -kNear) continue;
      // First half a, b, d: edge a-b is the +n side (d's weight wc small), d-a the start (wb small).
      // Second half c, d, b: edge c-d the -n side (b's weight wc small), b-c the end (wb small).
      const bool longEdge = x.wc < kNear;
      const bool endEdge = h == 0 ? (i == 0 && x.wb < kNear) : (i == quads - 1 && x.wb < kNear);
      const double along = h == 0 ? x.wb : 1.0 - x.wb;
      const double skipDepth = 2.0 * (radius[i] + along * (radius[i + 1] - radius[i]));
      const bool nearSkip = std::fabs(x.t * length - skipDepth) < kNear * std::max(1.0, skipDepth);
      // Seen almost edge-on (the quad's length nearly along the ray), its depth is ill-conditioned:
      // float rounding moves the hit along the ray by far more than the depth's rounding.
      const Vec normal = h == 0 ? cross(b - a, d - a) : cross(d - c, b - c);
      const bool edgeOn = std::fabs(dot(normal, unit)) < 0.05 * std::sqrt(dot(normal, normal));
      if (longEdge || endEdge || nearSkip || edgeOn) return true;
    }
  }
  return false;
}

// later: the curves' second time step (motion blur, rays at random times), or null.
// rate: the tessellation rate set on every geometry, negative for Embree's default (4).
// hermite: the Bezier curves alone, given as RTC_GEOMETRY_TYPE_FLAT_HERMITE_CURVE.
void expectRibbonsMatchEmbree(const CurveScene& data, const CurveScene* later, float rate, const char* what,
                              bool hermite = false) {
  const LoadedLibraries& libs = libraries();
  const auto commit = [&](const RtcLibrary& lib, RTCDevice device) {
    return hermite ? commitHermiteCurveScene(lib, device, data, later, RTC_GEOMETRY_TYPE_FLAT_HERMITE_CURVE, rate)
                   : commitCurveScene(lib, device, data, later, kFlatCurveTypes, rate);
  };
  RTCScene reference = commit(*libs.embree, libs.embreeDevice);
  RTCScene candidate = commit(*libs.obvh, libs.obvhDevice);
  ASSERT_EQ(libs.obvh->rtcGetDeviceError(libs.obvhDevice), RTC_ERROR_NONE);
  const int quads = rate < 0.f ? 4 : std::clamp(int(rate), 1, 16);

  const std::vector<RTCRay> rays = raysAtCurves(data, later);
  ShapeAnswerRules rules;
  rules.grazes = [&](const RTCRay& ray, const RTCHit& h) {
    const CurveScene placed = sceneAt(data, later, ray.time);
    return grazesRibbon(ray, int(h.geomID), &placed.vertices[h.geomID][data.segments[h.geomID][h.primID]], quads);
  };
  rules.jointTie = cubicJointTie;
  // Embree's v comes from float barycentrics across a ribbon far narrower than its distance to
  // the ray origin (measured up to 1.5e-4 off the double-precision answer).
  rules.vTolerance = 1e-3f;
  expectSameShapeAnswers(what, compareShapeAnswers(reference, candidate, rays, rules), rays.size(),
                         rays.size() / (hermite ? 30 : 10));
  libs.embree->rtcReleaseScene(reference);
  libs.obvh->rtcReleaseScene(candidate);
}

TEST(CrossvalFlatCurves, BezierBSplineAndCatmullRomMatchEmbree) {
  expectRibbonsMatchEmbree(makeCurveScene(15), nullptr, -1.f, "flat curves, default tessellation");
}

// Embree truncates the rate (7.5 gives 7 quads) and keeps it within [1, 16].
TEST(CrossvalFlatCurves, TessellationRatesMatchEmbree) {
  const CurveScene data = makeCurveScene(16);
  expectRibbonsMatchEmbree(data, nullptr, 7.5f, "flat curves, tessellation rate 7.5");
  expectRibbonsMatchEmbree(data, nullptr, 1.f, "flat curves, tessellation rate 1");
  expectRibbonsMatchEmbree(data, nullptr, 40.f, "flat curves, tessellation rate 40");
}

TEST(CrossvalFlatCurves, MovingCurvesMatchEmbree) {
  const CurveScene start = makeCurveScene(17), later = movedOn(start);
  expectRibbonsMatchEmbree(start, &later, -1.f, "moving flat curves");
}

// RTC_GEOMETRY_TYPE_FLAT_HERMITE_CURVE: vertices and tangents, still (default rate and 6) and moving.
TEST(CrossvalFlatCurves, HermiteCurvesMatchEmbree) {
  const CurveScene start = makeCurveScene(18), later = movedOn(start);
  expectRibbonsMatchEmbree(start, nullptr, -1.f, "flat Hermite curves", true);
  expectRibbonsMatchEmbree(start, nullptr, 6.f, "flat Hermite curves, tessellation rate 6", true);
  expectRibbonsMatchEmbree(start, &later, -1.f, "moving flat Hermite curves", true);
}

}  // namespace
}  // namespace obvh::test
