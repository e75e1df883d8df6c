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

#include "crossval_harness.h"
#include "ray_generation.h"
#include "shape_answers.h"

namespace obvh::test {
namespace {

struct Point4 {
  float x, y, z, r;
};

struct Basis {
  RTCGeometryType type;
  // The basis weights of the four control vertices at u and their derivatives.
  void (*weights)(double u, double w[4], double dw[4]);
};

void bezierWeights(double u, double w[4], double dw[4]) {
  const double s = 1.0 - u;
  w[0] = s * s * s, w[1] = 3 * s * s * u, w[2] = 3 * s * u * u, w[3] = u * u * u;
  dw[0] = -3 * s * s, dw[1] = 3 * s * s - 6 * s * u, dw[2] = 6 * s * u - 3 * u * u, dw[3] = 3 * u * u;
}
void bsplineWeights(double u, double w[4], double dw[4]) {
  const double s = 1.0 - u;
  w[0] = s * s * s / 6, w[1] = (3 * u * u * u - 6 * u * u + 4) / 6, w[2] = (-3 * u * u * u + 3 * u * u + 3 * u + 1) / 6,
  w[3] = u * u * u / 6;
  dw[0] = -s * s / 2, dw[1] = (9 * u * u - 12 * u) / 6, dw[2] = (-9 * u * u + 6 * u + 3) / 6, dw[3] = u * u / 2;
}
void catmullRomWeights(double u, double w[4], double dw[4]) {
  const double u2 = u * u, u3 = u2 * u;
  w[0] = (-u3 + 2 * u2 - u) / 2, w[1] = (3 * u3 - 5 * u2 + 2) / 2, w[2] = (-3 * u3 + 4 * u2 + u) / 2,
  w[3] = (u3 - u2) / 2;
  dw[0] = (-3 * u2 + 4 * u - 1) / 2, dw[1] = (9 * u2 - 10 * u) / 2, dw[2] = (-9 * u2 + 8 * u + 1) / 2,
  dw[3] = (3 * u2 - 2 * u) / 2;
}

const Basis kBases[3] = {{RTC_GEOMETRY_TYPE_ROUND_BEZIER_CURVE, bezierWeights},
                         {RTC_GEOMETRY_TYPE_ROUND_BSPLINE_CURVE, bsplineWeights},
                         {RTC_GEOMETRY_TYPE_ROUND_CATMULL_ROM_CURVE, catmullRomWeights}};

// One geometry per basis (geomID = basis index): curves of two segments, bent in all three axes,
// on a grid of cells 3 apart so that no two curves come close; radii vary along each curve.
struct CurveScene {
  std::vector<Point4> vertices[3];
  std::vector<uint32_t> segments[3];
};

// The largest radius times curvature along the segment whose control vertices are c (sampled).
// Where it reaches 1 the tube overlaps itself, and its circles no longer make one surface: obvh
// and Embree then answer differently (each finds some of the overlapping walls), so the scene
// keeps well clear of that, as hair and fibres do.
double largestBend(const Basis& basis, const Point4* c) {
  double worst = 0.0;
  const auto derivative = [&](double u, double out[3], double& r) {
    double w[4], dw[4];
    basis.weights(u, w, dw);
    r = 0;
    for (int a = 0; a < 3; ++a) out[a] = 0;
    for (int k = 0; k < 4; ++k) {
      out[0] += dw[k] * c[k].x, out[1] += dw[k] * c[k].y, out[2] += dw[k] * c[k].z;
      r += w[k] * c[k].r;
    }
  };
  for (int step = 0; step <= 256; ++step) {
    const double u = step / 256.0, h = 1e-5;
    double d0[3], d1[3], r, unused;
    derivative(u, d0, r);
    derivative(u + h, d1, unused);
    double dd[3], cr[3];
    for (int a = 0; a < 3; ++a) dd[a] = (d1[a] - d0[a]) / h;
    cr[0] = d0[1] * dd[2] - d0[2] * dd[1], cr[1] = d0[2] * dd[0] - d0[0] * dd[2], cr[2] = d0[0] * dd[1] - d0[1] * dd[0];
    const double speed = std::sqrt(d0[0] * d0[0] + d0[1] * d0[1] + d0[2] * d0[2]);
    const double curvature = std::sqrt(cr[0] * cr[0] + cr[1] * cr[1] + cr[2] * cr[2]) / (speed * speed * speed);
    worst = std::max(worst, r * curvature);
  }
  return worst;
}

CurveScene makeScene(uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> unit(0.f, 1.f);
  CurveScene scene;
  for (int b = 0; b < 3; ++b)
    for (int k = 0; k < 40; ++k) {
      const float cx = 3.f * float(k % 8), cy = 3.f * float(k / 8) + 16.f * float(b);
      // Bezier segments share their end vertex (0..3, 3..6); the others use a sliding window (0..3, 1..4).
      const int count = b == 0 ? 7 : 5;
      std::vector<Point4> curve;
      do {
        curve.clear();
        for (int v = 0; v < count; ++v)
          curve.push_back({cx + 2.2f * float(v) / float(count - 1) + 0.1f * unit(rng), cy + 0.8f * unit(rng),
                           1.5f * unit(rng), 0.02f + 0.1f * unit(rng)});
      } while (largestBend(kBases[b], &curve[0]) > 0.5 || largestBend(kBases[b], &curve[b == 0 ? 3 : 1]) > 0.5);
      const uint32_t first = uint32_t(scene.vertices[b].size());
      scene.vertices[b].insert(scene.vertices[b].end(), curve.begin(), curve.end());
      scene.segments[b].push_back(first);
      scene.segments[b].push_back(first + (b == 0 ? 3 : 1));
    }
  return scene;
}

// The scene moved on (motion blur's second time step): curves slide along x by less than the
// spacing of the grid and thicken a little.
CurveScene movedOn(CurveScene scene) {
  for (std::vector<Point4>& points : scene.vertices)
    for (Point4& p : points) p.x += 0.5f, p.z -= 0.3f, p.r *= 1.2f;
  return scene;
}

// The scene at a ray's time between its two steps, blended as both libraries blend time steps.
CurveScene sceneAt(const CurveScene& first, const CurveScene* later, float time) {
  if (!later) return first;
  CurveScene at = first;
  for (int b = 0; b < 3; ++b)
    for (size_t k = 0; k < at.vertices[b].size(); ++k) {
      const Point4 &p = first.vertices[b][k], &q = later->vertices[b][k];
      at.vertices[b][k] = {p.x * (1.f - time) + q.x * time, p.y * (1.f - time) + q.y * time,
                           p.z * (1.f - time) + q.z * time, p.r * (1.f - time) + q.r * time};
    }
  return at;
}

// later: the vertices of a second time step (motion blur), or null.
RTCScene commit(const RtcLibrary& lib, RTCDevice device, const CurveScene& data, const CurveScene* later) {
  RTCScene scene = lib.rtcNewScene(device);
  for (int b = 0; b < 3; ++b) {
    RTCGeometry g = lib.rtcNewGeometry(device, kBases[b].type);
    if (later) lib.rtcSetGeometryTimeStepCount(g, 2);
    for (unsigned step = 0; step < (later ? 2u : 1u); ++step) {
      const std::vector<Point4>& points = step == 0 ? data.vertices[b] : later->vertices[b];
      void* v = lib.rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, step, RTC_FORMAT_FLOAT4, 16, points.size());
      std::memcpy(v, points.data(), points.size() * sizeof(Point4));
    }
    void* i = lib.rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT, 4, data.segments[b].size());
    std::memcpy(i, data.segments[b].data(), data.segments[b].size() * sizeof(uint32_t));
    lib.rtcCommitGeometry(g);
    lib.rtcAttachGeometry(scene, g);
    lib.rtcReleaseGeometry(g);
  }
  lib.rtcCommitScene(scene);
  return scene;
}

// How far outside (positive) or inside (negative) of the tube's outline the ray passes, relative
// to the radius: the least over sampled u of where the ray crosses the plane of the circle at u;
// and the same at the two ends alone (the rims of the open ends).
struct Margins {
  double outline = 1e300, start = 1e300, end = 1e300;
};

Margins margins(const RTCRay& ray, const Basis& basis, const Point4* control) {
  const double o[3] = {ray.org_x, ray.org_y, ray.org_z}, d[3] = {ray.dir_x, ray.dir_y, ray.dir_z};
  Margins m;
  constexpr int kSteps = 8192;
  for (int step = 0; step <= kSteps; ++step) {
    const double u = double(step) / kSteps;
    double w[4], dw[4], p[3] = {0, 0, 0}, dp[3] = {0, 0, 0}, r = 0;
    basis.weights(u, w, dw);
    for (int k = 0; k < 4; ++k) {
      const double c[3] = {control[k].x, control[k].y, control[k].z};
      for (int a = 0; a < 3; ++a) p[a] += w[k] * c[a], dp[a] += dw[k] * c[a];
      r += w[k] * control[k].r;
    }
    const double across = d[0] * dp[0] + d[1] * dp[1] + d[2] * dp[2];
    if (std::fabs(across) < 1e-12) continue;
    const double t = ((p[0] - o[0]) * dp[0] + (p[1] - o[1]) * dp[1] + (p[2] - o[2]) * dp[2]) / across;
    double dist2 = 0;
    for (int a = 0; a < 3; ++a) dist2 += std::pow(o[a] + t * d[a] - p[a], 2);
    const double margin = std::sqrt(dist2) / r - 1.0;
    m.outline = std::min(m.outline, margin);
    if (step == 0) m.start = margin;
    if (step == kSteps) m.end = margin;
  }
  return m;
}

// later: the curves' second time step (motion blur, rays at random times), or null.
void expectCurvesMatchEmbree(const CurveScene& data, const CurveScene* later) {
  const LoadedLibraries& libs = libraries();
  RTCScene reference = commit(*libs.embree, libs.embreeDevice, data, later);
  RTCScene candidate = commit(*libs.obvh, libs.obvhDevice, data, later);
  ASSERT_EQ(libs.obvh->rtcGetDeviceError(libs.obvhDevice), RTC_ERROR_NONE);

  std::vector<RTCRay> rays = tools::randomRays(tools::SceneBox{{-1.f, -1.f, -1.f}, {25.f, 48.f, 3.f}}, 60000, 21);
  if (later) assignRandomTimes(rays, 23);
  std::mt19937 rng(22);
  std::uniform_real_distribution<float> unit(-1.f, 1.f);
  for (int b = 0; b < 3; ++b)
    for (uint32_t first : data.segments[b])
      for (int k = 0; k < 150; ++k) {  // aimed near points of every segment's tube, from all sides
        // A moving curve is aimed at where it is at the ray's time.
        const float time = later ? 0.5f + 0.5f * unit(rng) : 0.f;
        const CurveScene placed = sceneAt(data, later, time);
        const Point4* c = &placed.vertices[b][first];
        double w[4], dw[4];
        kBases[b].weights(0.5 + 0.55 * double(unit(rng)), w, dw);  // a little past the ends too
        float target[3] = {0.f, 0.f, 0.f}, r = 0.f;
        for (int v = 0; v < 4; ++v) {
          target[0] += float(w[v]) * c[v].x, target[1] += float(w[v]) * c[v].y, target[2] += float(w[v]) * c[v].z;
          r += float(w[v]) * c[v].r;
        }
        for (float& t : target) t += 1.5f * r * unit(rng);
        const float dir[3] = {unit(rng), unit(rng), unit(rng)};
        const float back = k % 4 == 0 ? 0.5f * r : 5.f;  // some start inside or right beside the tube
        RTCRay ray{};
        ray.org_x = target[0] - back * dir[0], ray.org_y = target[1] - back * dir[1], ray.org_z = target[2] - back * dir[2];
        ray.dir_x = dir[0], ray.dir_y = dir[1], ray.dir_z = dir[2];
        ray.tnear = 0.f, ray.tfar = INFINITY, ray.mask = 0xFFFFFFFFu, ray.time = time;
        rays.push_back(ray);
      }

  ShapeAnswerRules rules;
  rules.grazes = [&](const RTCRay& ray, const RTCHit& h) {
    const CurveScene placed = sceneAt(data, later, ray.time);  // where the curves are for this ray
    const Margins m = margins(ray, kBases[h.geomID], &placed.vertices[h.geomID][data.segments[h.geomID][h.primID]]);
    return std::fabs(m.outline) < 2e-3 || std::fabs(m.start) < 2e-3 || std::fabs(m.end) < 2e-3;
  };
  // Two segments of one curve meet at a joint: a ray through it hits both at one depth.
  rules.jointTie = [&](const RTCRayHit& embree, const RTCRayHit& obvh) {
    const RTCHit &e = embree.hit, &o = obvh.hit;
    if (e.geomID != o.geomID || e.geomID == RTC_INVALID_GEOMETRY_ID || e.primID / 2 != o.primID / 2) return false;
    const float te = embree.ray.tfar, to = obvh.ray.tfar;
    const RTCHit& first = e.primID < o.primID ? e : o;
    const RTCHit& second = e.primID < o.primID ? o : e;
    return std::fabs(te - to) <= 1e-3f * std::max(1.f, te) && first.u > 0.99f && second.u < 0.01f;
  };
  // Embree's Ng comes from its float solution, in which the radius' slope term loses digits.
  rules.ngTolerance = 1e-2f;
  expectSameShapeAnswers(later ? "moving round curves" : "round curves",
                         compareShapeAnswers(reference, candidate, rays, rules), rays.size(), rays.size() / 5);
  libs.embree->rtcReleaseScene(reference);
  libs.obvh->rtcReleaseScene(candidate);
}

TEST(CrossvalRoundCurves, BezierBSplineAndCatmullRomMatchEmbree) { expectCurvesMatchEmbree(makeScene(5), nullptr); }

// Motion blur: two time steps, rays at random times.
TEST(CrossvalRoundCurves, MovingCurvesMatchEmbree) {
  const CurveScene start = makeScene(6), later = movedOn(start);
  expectCurvesMatchEmbree(start, &later);
}

// rtcInterpolate along curve segments (the vertices and a vertex attribute, with first and second
// derivatives in u), flat linear curves included.
TEST(CrossvalCurveInterpolation, EveryBasisMatchesEmbree) {
  const LoadedLibraries& libs = libraries();
  const CurveScene data = makeScene(9);
  std::mt19937 rng(10);
  std::uniform_real_distribution<float> unit(0.f, 1.f);
  const RtcLibrary* lib[2] = {libs.embree, libs.obvh};
  RTCDevice devices[2] = {libs.embreeDevice, libs.obvhDevice};
  const RTCGeometryType types[4] = {RTC_GEOMETRY_TYPE_FLAT_LINEAR_CURVE, kBases[0].type, kBases[1].type, kBases[2].type};
  size_t compared = 0;
  for (int b = 0; b < 4; ++b) {
    const std::vector<Point4>& vertices = data.vertices[std::max(b - 1, 0)];
    std::vector<uint32_t> segments = data.segments[std::max(b - 1, 0)];
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
  EXPECT_EQ(compared, 4000u);
}

}  // namespace
}  // namespace obvh::test
