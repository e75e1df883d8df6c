// The cubic-curve scene the round and the flat curve cross-validations share: one geometry per
// basis (geomID 0 Bezier, 1 B-spline, 2 Catmull-Rom), each of 40 curves of two segments, bent in
// all three axes, on a grid of cells 3 apart so that no two curves come close; radii vary along
// each curve. Its rays, and the curve evaluated in double precision in its own basis (the tests'
// oracles; not through obvh's code).
#pragma once

#include <cstdint>
#include <vector>

#include "crossval_harness.h"

namespace obvh::test {

struct Point4 {
  float x, y, z, r;
};

// The weights of a segment's four control vertices at u, and their derivatives.
using BasisWeights = void (*)(double u, double w[4], double dw[4]);
extern const BasisWeights kBasisWeights[3];  // Bezier, B-spline, Catmull-Rom

constexpr RTCGeometryType kRoundCurveTypes[3] = {RTC_GEOMETRY_TYPE_ROUND_BEZIER_CURVE,
                                                 RTC_GEOMETRY_TYPE_ROUND_BSPLINE_CURVE,
                                                 RTC_GEOMETRY_TYPE_ROUND_CATMULL_ROM_CURVE};
constexpr RTCGeometryType kFlatCurveTypes[3] = {RTC_GEOMETRY_TYPE_FLAT_BEZIER_CURVE,
                                                RTC_GEOMETRY_TYPE_FLAT_BSPLINE_CURVE,
                                                RTC_GEOMETRY_TYPE_FLAT_CATMULL_ROM_CURVE};

struct CurveScene {
  std::vector<Point4> vertices[3];
  std::vector<uint32_t> segments[3];  // each segment's first control vertex
};

CurveScene makeCurveScene(uint32_t seed);
// The scene moved on (motion blur's second time step): curves slide along x by less than the
// spacing of the grid and thicken a little.
CurveScene movedOn(CurveScene scene);
// The scene at a ray's time between its two steps, blended as both libraries blend time steps.
CurveScene sceneAt(const CurveScene& first, const CurveScene* later, float time);

// types[b]: the geometry type of basis b; later: the vertices of a second time step (motion blur),
// or null; tessellationRate: set on every geometry when not negative.
RTCScene commitCurveScene(const RtcLibrary& lib, RTCDevice device, const CurveScene& data, const CurveScene* later,
                          const RTCGeometryType types[3], float tessellationRate = -1.f);

// The scene's Bezier curves (geometry 0) as Hermite curves of the given type, geomID 0: each
// segment its own two vertices with tangents 3 (p1 - p0) and 3 (p3 - p2), the same curve.
RTCScene commitHermiteCurveScene(const RtcLibrary& lib, RTCDevice device, const CurveScene& data,
                                 const CurveScene* later, RTCGeometryType type, float tessellationRate = -1.f);

// Random rays through the scene's box, and rays aimed near points of every segment (a little past
// its ends too) from all sides, a quarter starting inside or right beside the curve; at random
// times when the scene moves.
std::vector<RTCRay> raysAtCurves(const CurveScene& data, const CurveScene* later);

// Two segments of one curve (primIDs 2k, 2k + 1) meet at a joint: a ray through it hits both at
// one depth, and either answer is right.
bool cubicJointTie(const RTCRayHit& embree, const RTCRayHit& obvh);

struct CurvePoint {
  double p[3], dp[3], r;  // position, its derivative in u, radius
};
CurvePoint evaluateCurve(int basis, const Point4* control, double u);

}  // namespace obvh::test
