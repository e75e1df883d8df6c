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

// later: the curves' second time step (motion blur, rays at random times), or null.
void expectCurvesMatchEmbree(const CurveScene& data, const CurveScene* later) {
  const LoadedLibraries& libs = libraries();
  RTCScene reference = commitCurveScene(*libs.embree, libs.embreeDevice, data, later, kRoundCurveTypes);
  RTCScene candidate = commitCurveScene(*libs.obvh, libs.obvhDevice, data, later, kRoundCurveTypes);
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
  expectSameShapeAnswers(later ? "moving round curves" : "round curves",
                         compareShapeAnswers(reference, candidate, rays, rules), rays.size(), rays.size() / 5);
  libs.embree->rtcReleaseScene(reference);
  libs.obvh->rtcReleaseScene(candidate);
}

TEST(CrossvalRoundCurves, BezierBSplineAndCatmullRomMatchEmbree) { expectCurvesMatchEmbree(makeCurveScene(5), nullptr); }

// Motion blur: two time steps, rays at random times.
TEST(CrossvalRoundCurves, MovingCurvesMatchEmbree) {
  const CurveScene start = makeCurveScene(6), later = movedOn(start);
  expectCurvesMatchEmbree(start, &later);
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
    for (int k = 0; k < 2; ++k) {
      g[k] = lib[k]->rtcNewGeometry(devices[k], types[b]);
      lib[k]->rtcSetSharedGeometryBuffer(g[k], RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT4, vertices.data(), 0, 16,
                                         vertices.size());
      lib[k]->rtcSetSharedGeometryBuffer(g[k], RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT, segments.data(), 0, 4,
                                         segments.size());
      lib[k]->rtcSetGeometryVertexAttributeCount(g[k], 1);
      lib[k]->rtcSetSharedGeometryBuffer(g[k], RTC_BUFFER_TYPE_VERTEX_ATTRIBUTE, 0, RTC_FORMAT_FLOAT3, attribute.data(),
                                         0, 12, vertices.size());
      lib[k]->rtcCommitGeometry(g[k]);
    }
    for (int n = 0; n < 500; ++n) {
      const unsigned prim = unsigned(rng() % segments.size());
      const float u = n % 10 == 0 ? float(n % 20 == 0) : unit(rng), v = unit(rng);
      for (RTCBufferType type : {RTC_BUFFER_TYPE_VERTEX, RTC_BUFFER_TYPE_VERTEX_ATTRIBUTE}) {
        const unsigned count = type == RTC_BUFFER_TYPE_VERTEX ? 4 : 3;
        float out[2][6][4];
        for (auto& library : out)  // what neither library writes must stay as it was
          for (auto& part : library) std::fill(part, part + 4, -7.f);
        for (int k = 0; k < 2; ++k) {
          RTCInterpolateArguments args{g[k], prim, u, v, type, 0, out[k][0], out[k][1], out[k][2], out[k][3], out[k][4],
                                       out[k][5], count};
          lib[k]->rtcInterpolate(&args);
        }
        for (int part = 0; part < 6; ++part)
          for (unsigned c = 0; c < count; ++c)
            EXPECT_NEAR(out[0][part][c], out[1][part][c], 1e-4f * (1.f + std::fabs(out[0][part][c])))
                << "type " << types[b] << " prim " << prim << " u " << u << " part " << part;
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

}  // namespace
}  // namespace obvh::test
