// Round cubic curves (RTC_GEOMETRY_TYPE_ROUND_BEZIER_CURVE, _ROUND_BSPLINE_CURVE,
// _ROUND_CATMULL_ROM_CURVE) through obvh and Debian's Embree: the same primitive on every ray, and
// t, u, Ng within rounding (Embree solves in float). Answers may differ only where the ray grazes
// the tube's silhouette or the rim of its open ends, or crosses the joint of two segments; each
// such claim is checked here in double precision by sampling the curve in its own basis (not
// through obvh's Bezier form).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <random>

#include "curve_scene.h"
#include "shape_answers.h"

namespace obvh::test {
namespace {

// How far outside (positive) or inside (negative) of the tube's outline the ray passes, relative
// to the radius: the least over sampled u of where the ray crosses the plane of the circle at u;
// and the same at the two ends alone (the rims of the open ends).
struct Margins {
  double outline = 1e300, start = 1e300, end = 1e300;
};

Margins margins(const RTCRay& ray, int basis, const Point4* control) {
  const double o[3] = {ray.org_x, ray.org_y, ray.org_z}, d[3] = {ray.dir_x, ray.dir_y, ray.dir_z};
  Margins m;
  constexpr int kSteps = 8192;
  for (int step = 0; step <= kSteps; ++step) {
    const CurvePoint e = evaluateCurve(basis, control, double(step) / kSteps);
    const double across = d[0] * e.dp[0] + d[1] * e.dp[1] + d[2] * e.dp[2];
    if (std::fabs(across) < 1e-12) continue;
    const double t = ((e.p[0] - o[0]) * e.dp[0] + (e.p[1] - o[1]) * e.dp[1] + (e.p[2] - o[2]) * e.dp[2]) / across;
    double dist2 = 0;
    for (int a = 0; a < 3; ++a) dist2 += std::pow(o[a] + t * d[a] - e.p[a], 2);
    const double margin = std::sqrt(dist2) / e.r - 1.0;
    m.outline = std::min(m.outline, margin);
    if (step == 0) m.start = margin;
    if (step == kSteps) m.end = margin;
  }
  return m;
}

// later: the curves' second time step (motion blur, rays at random times), or null; hermite: the
// Bezier curves alone, given as RTC_GEOMETRY_TYPE_ROUND_HERMITE_CURVE.
void expectCurvesMatchEmbree(const CurveScene& data, const CurveScene* later, bool hermite = false) {
  const LoadedLibraries& libs = libraries();
  const auto commit = [&](const RtcLibrary& lib, RTCDevice device) {
    return hermite ? commitHermiteCurveScene(lib, device, data, later, RTC_GEOMETRY_TYPE_ROUND_HERMITE_CURVE)
                   : commitCurveScene(lib, device, data, later, kRoundCurveTypes);
  };
  RTCScene reference = commit(*libs.embree, libs.embreeDevice);
  RTCScene candidate = commit(*libs.obvh, libs.obvhDevice);
  ASSERT_EQ(libs.obvh->rtcGetDeviceError(libs.obvhDevice), RTC_ERROR_NONE);

  const std::vector<RTCRay> rays = raysAtCurves(data, later);
  ShapeAnswerRules rules;
  rules.grazes = [&](const RTCRay& ray, const RTCHit& h) {
    const CurveScene placed = sceneAt(data, later, ray.time);  // where the curves are for this ray
    const Margins m = margins(ray, int(h.geomID), &placed.vertices[h.geomID][data.segments[h.geomID][h.primID]]);
    return std::fabs(m.outline) < 2e-3 || std::fabs(m.start) < 2e-3 || std::fabs(m.end) < 2e-3;
  };
  rules.jointTie = cubicJointTie;
  // Embree's Ng comes from its float solution, in which the radius' slope term loses digits.
  rules.ngTolerance = 1e-2f;
  expectSameShapeAnswers(hermite ? (later ? "moving round Hermite curves" : "round Hermite curves")
                                 : (later ? "moving round curves" : "round curves"),
                         compareShapeAnswers(reference, candidate, rays, rules), rays.size(),
                         rays.size() / (hermite ? 15 : 5));
  libs.embree->rtcReleaseScene(reference);
  libs.obvh->rtcReleaseScene(candidate);
}

TEST(CrossvalRoundCurves, BezierBSplineAndCatmullRomMatchEmbree) { expectCurvesMatchEmbree(makeCurveScene(5), nullptr); }

// Motion blur: two time steps, rays at random times.
TEST(CrossvalRoundCurves, MovingCurvesMatchEmbree) {
  const CurveScene start = makeCurveScene(6), later = movedOn(start);
  expectCurvesMatchEmbree(start, &later);
}

// RTC_GEOMETRY_TYPE_ROUND_HERMITE_CURVE: vertices and tangents (RTC_BUFFER_TYPE_TANGENT), still and moving.
TEST(CrossvalRoundCurves, HermiteCurvesMatchEmbree) {
  const CurveScene start = makeCurveScene(7), later = movedOn(start);
  expectCurvesMatchEmbree(start, nullptr, true);
  expectCurvesMatchEmbree(start, &later, true);
}

// A committed curve geometry over shared buffers: float4 vertices, tangents (Hermite curves; else
// null), segment starts and one float3 vertex attribute.
RTCGeometry interpolatedCurve(const RtcLibrary& lib, RTCDevice device, RTCGeometryType type,
                              const std::vector<Point4>& vertices, const std::vector<Point4>* tangents,
                              const std::vector<uint32_t>& segments, const std::vector<float>& attribute) {
  RTCGeometry g = lib.rtcNewGeometry(device, type);
  lib.rtcSetSharedGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT4, vertices.data(), 0, 16, vertices.size());
  if (tangents)
    lib.rtcSetSharedGeometryBuffer(g, RTC_BUFFER_TYPE_TANGENT, 0, RTC_FORMAT_FLOAT4, tangents->data(), 0, 16,
                                   tangents->size());
  lib.rtcSetSharedGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT, segments.data(), 0, 4, segments.size());
  lib.rtcSetGeometryVertexAttributeCount(g, 1);
  lib.rtcSetSharedGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX_ATTRIBUTE, 0, RTC_FORMAT_FLOAT3, attribute.data(), 0, 12,
                                 attribute.size() / 3);
  lib.rtcCommitGeometry(g);
  return g;
}

// rtcInterpolate through Embree (g[0]) and obvh (g[1]) on slot 0 of the buffer type: every output
// within 1e-4, and what neither library writes left as it was.
void expectSameInterpolation(RTCGeometry g[2], unsigned prim, float u, float v, RTCBufferType type, unsigned count,
                             RTCGeometryType geometryType) {
  const LoadedLibraries& libs = libraries();
  const RtcLibrary* lib[2] = {libs.embree, libs.obvh};
  float out[2][6][4];
  for (auto& library : out)
    for (auto& part : library) std::fill(part, part + 4, -7.f);
  for (int k = 0; k < 2; ++k) {
    RTCInterpolateArguments args{g[k], prim, u, v, type, 0, out[k][0], out[k][1], out[k][2], out[k][3], out[k][4],
                                 out[k][5], count};
    lib[k]->rtcInterpolate(&args);
  }
  for (int part = 0; part < 6; ++part)
    for (unsigned c = 0; c < count; ++c)
      EXPECT_NEAR(out[0][part][c], out[1][part][c], 1e-4f * (1.f + std::fabs(out[0][part][c])))
          << "geometry type " << geometryType << " buffer type " << type << " prim " << prim << " u " << u
          << " part " << part;
}

// rtcInterpolate along curve segments (the vertices and a vertex attribute, with first and second
// derivatives in u), flat linear and flat cubic curves included.
TEST(CrossvalCurveInterpolation, EveryBasisMatchesEmbree) {
  const LoadedLibraries& libs = libraries();
  const CurveScene data = makeCurveScene(9);
  std::mt19937 rng(10);
  std::uniform_real_distribution<float> unit(0.f, 1.f);
  const RtcLibrary* lib[2] = {libs.embree, libs.obvh};
  RTCDevice devices[2] = {libs.embreeDevice, libs.obvhDevice};
  // The scene's vertices and segments of basis (b - 1) % 3, for linear curves those of the Bezier one.
  const RTCGeometryType types[7] = {RTC_GEOMETRY_TYPE_FLAT_LINEAR_CURVE,
                                    kRoundCurveTypes[0], kRoundCurveTypes[1], kRoundCurveTypes[2],
                                    kFlatCurveTypes[0], kFlatCurveTypes[1], kFlatCurveTypes[2]};
  size_t compared = 0;
  for (int b = 0; b < 7; ++b) {
    const int basis = b == 0 ? 0 : (b - 1) % 3;
    const std::vector<Point4>& vertices = data.vertices[basis];
    std::vector<uint32_t> segments = data.segments[basis];
    std::vector<float> attribute(vertices.size() * 3);
    for (float& a : attribute) a = 10.f * unit(rng);
    RTCGeometry g[2];
    for (int k = 0; k < 2; ++k)
      g[k] = interpolatedCurve(*lib[k], devices[k], types[b], vertices, nullptr, segments, attribute);
    for (int n = 0; n < 500; ++n) {
      const unsigned prim = unsigned(rng() % segments.size());
      const float u = n % 10 == 0 ? float(n % 20 == 0) : unit(rng), v = unit(rng);
      for (RTCBufferType type : {RTC_BUFFER_TYPE_VERTEX, RTC_BUFFER_TYPE_VERTEX_ATTRIBUTE}) {
        expectSameInterpolation(g, prim, u, v, type, type == RTC_BUFFER_TYPE_VERTEX ? 4 : 3, types[b]);
        ++compared;
      }
    }
    for (int k = 0; k < 2; ++k) {
      EXPECT_EQ(lib[k]->rtcGetDeviceError(devices[k]), RTC_ERROR_NONE);
      lib[k]->rtcReleaseGeometry(g[k]);
    }
  }
  EXPECT_EQ(compared, 7000u);
}

// rtcInterpolate on Hermite curves: vertex and tangent buffers (Embree answers both with the
// Hermite basis over vertices and tangents) and a vertex attribute (linear between the two vertices).
TEST(CrossvalCurveInterpolation, HermiteMatchesEmbree) {
  const LoadedLibraries& libs = libraries();
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> unit(-1.f, 1.f);
  std::vector<Point4> vertices(40), tangents(40);
  std::vector<float> attribute(40 * 3);
  for (size_t k = 0; k < vertices.size(); ++k) {
    vertices[k] = {4.f * unit(rng), 4.f * unit(rng), 4.f * unit(rng), 0.2f + 0.1f * unit(rng)};
    tangents[k] = {3.f * unit(rng), 3.f * unit(rng), 3.f * unit(rng), 0.1f * unit(rng)};
  }
  for (float& a : attribute) a = 10.f * unit(rng);
  std::vector<uint32_t> segments;
  for (uint32_t k = 0; k + 1 < vertices.size(); k += 2) segments.push_back(k);
  const RtcLibrary* lib[2] = {libs.embree, libs.obvh};
  RTCDevice devices[2] = {libs.embreeDevice, libs.obvhDevice};
  RTCGeometry g[2];
  for (int k = 0; k < 2; ++k)
    g[k] = interpolatedCurve(*lib[k], devices[k], RTC_GEOMETRY_TYPE_ROUND_HERMITE_CURVE, vertices, &tangents, segments,
                             attribute);
  size_t compared = 0;
  for (int n = 0; n < 300; ++n) {
    const unsigned prim = unsigned(rng() % segments.size());
    const float u = 0.5f + 0.5f * unit(rng);
    for (RTCBufferType type : {RTC_BUFFER_TYPE_VERTEX, RTC_BUFFER_TYPE_TANGENT, RTC_BUFFER_TYPE_VERTEX_ATTRIBUTE}) {
      expectSameInterpolation(g, prim, u, 0.5f, type, type == RTC_BUFFER_TYPE_VERTEX_ATTRIBUTE ? 3 : 4,
                              RTC_GEOMETRY_TYPE_ROUND_HERMITE_CURVE);
      ++compared;
    }
  }
  for (int k = 0; k < 2; ++k) {
    EXPECT_EQ(lib[k]->rtcGetDeviceError(devices[k]), RTC_ERROR_NONE);
    lib[k]->rtcReleaseGeometry(g[k]);
  }
  EXPECT_EQ(compared, 900u);
}

}  // namespace
}  // namespace obvh::test
