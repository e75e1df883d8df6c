// Sphere points and flat linear curves (RTC_GEOMETRY_TYPE_SPHERE_POINT, _FLAT_LINEAR_CURVE) through
// obvh and Debian's Embree: the same primitive on every ray, t, Ng and u within rounding; a ray
// may see another answer only where it grazes a silhouette (checked in double precision here).
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

struct ShapeScene {
  std::vector<Point4> spheres;
  std::vector<Point4> curveVertices;
  std::vector<uint32_t> segments;  // first vertex of each segment
};

// Spheres on one grid, curve segments (two or three in a row, sharing vertices) on another, so no
// two primitives overlap and every hit away from a silhouette has one right answer.
ShapeScene makeScene(uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> unit(0.f, 1.f);
  ShapeScene scene;
  for (int k = 0; k < 300; ++k)
    scene.spheres.push_back({float(k % 15) + 0.5f, float(k / 15) + 0.5f, 2.f * unit(rng), 0.1f + 0.3f * unit(rng)});
  for (int k = 0; k < 120; ++k) {
    const float cx = 20.f + 2.f * float(k % 10), cy = 2.f * float(k / 10);
    const int pieces = 1 + k % 2;
    const uint32_t first = uint32_t(scene.curveVertices.size());
    for (int v = 0; v <= pieces; ++v)
      scene.curveVertices.push_back({cx + 1.6f * unit(rng), cy + 1.6f * unit(rng), 2.f * unit(rng), 0.02f + 0.15f * unit(rng)});
    for (int p = 0; p < pieces; ++p) scene.segments.push_back(first + uint32_t(p));
  }
  return scene;
}

// The scene moved on (motion blur's second time step): everything slides along x by less than the
// spacing of the grids and radii grow, so no two primitives overlap at any time.
ShapeScene movedOn(ShapeScene scene) {
  for (std::vector<Point4>* points : {&scene.spheres, &scene.curveVertices})
    for (Point4& p : *points) p.x += 0.4f, p.z -= 0.3f, p.r *= 1.15f;
  return scene;
}

// The scene at a ray's time between its two steps, blended as both libraries blend time steps.
ShapeScene sceneAt(const ShapeScene& first, const ShapeScene* later, float time) {
  if (!later) return first;
  ShapeScene at = first;
  const auto blend = [&](const std::vector<Point4>& a, const std::vector<Point4>& b, std::vector<Point4>& out) {
    for (size_t k = 0; k < a.size(); ++k)
      out[k] = {a[k].x * (1.f - time) + b[k].x * time, a[k].y * (1.f - time) + b[k].y * time,
                a[k].z * (1.f - time) + b[k].z * time, a[k].r * (1.f - time) + b[k].r * time};
  };
  blend(first.spheres, later->spheres, at.spheres);
  blend(first.curveVertices, later->curveVertices, at.curveVertices);
  return at;
}

// later: the vertices of a second time step (motion blur), or null.
RTCScene commit(const RtcLibrary& lib, RTCDevice device, const ShapeScene& data, const ShapeScene* later = nullptr) {
  RTCScene scene = lib.rtcNewScene(device);
  const auto setVertices = [&](RTCGeometry g, const std::vector<Point4>& first, const std::vector<Point4>* second) {
    if (second) lib.rtcSetGeometryTimeStepCount(g, 2);
    for (unsigned step = 0; step < (second ? 2u : 1u); ++step) {
      const std::vector<Point4>& points = step == 0 ? first : *second;
      void* v = lib.rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, step, RTC_FORMAT_FLOAT4, 16, points.size());
      std::memcpy(v, points.data(), points.size() * sizeof(Point4));
    }
  };
  RTCGeometry spheres = lib.rtcNewGeometry(device, RTC_GEOMETRY_TYPE_SPHERE_POINT);
  setVertices(spheres, data.spheres, later ? &later->spheres : nullptr);
  lib.rtcCommitGeometry(spheres);
  lib.rtcAttachGeometry(scene, spheres);
  lib.rtcReleaseGeometry(spheres);
  RTCGeometry curves = lib.rtcNewGeometry(device, RTC_GEOMETRY_TYPE_FLAT_LINEAR_CURVE);
  setVertices(curves, data.curveVertices, later ? &later->curveVertices : nullptr);
  void* ci = lib.rtcSetNewGeometryBuffer(curves, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT, 4, data.segments.size());
  std::memcpy(ci, data.segments.data(), data.segments.size() * sizeof(uint32_t));
  lib.rtcCommitGeometry(curves);
  lib.rtcAttachGeometry(scene, curves);
  lib.rtcReleaseGeometry(curves);
  lib.rtcCommitScene(scene);
  return scene;
}

// How far inside (negative) or outside (positive) of the primitive's silhouette the ray passes,
// relative to its radius, in double precision; the independent oracle for differing answers.
double silhouetteMargin(const RTCRay& ray, const Point4& a, const Point4* b) {
  const double d[3] = {ray.dir_x, ray.dir_y, ray.dir_z};
  const double o[3] = {ray.org_x, ray.org_y, ray.org_z};
  const double dd = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
  const auto offset = [&](const double p[3], double out[3]) {  // p's offset from the ray line
    const double t = ((p[0] - o[0]) * d[0] + (p[1] - o[1]) * d[1] + (p[2] - o[2]) * d[2]) / dd;
    for (int k = 0; k < 3; ++k) out[k] = p[k] - o[k] - t * d[k];
  };
  const double pa[3] = {a.x, a.y, a.z};
  double xa[3];
  offset(pa, xa);
  if (!b) return std::sqrt(xa[0] * xa[0] + xa[1] * xa[1] + xa[2] * xa[2]) / a.r - 1.0;
  const double pb[3] = {b->x, b->y, b->z};
  double xb[3];
  offset(pb, xb);
  double best = 1e300;
  for (int step = 0; step <= 4096; ++step) {  // sampled: the oracle must not share obvh's formula
    const double u = step / 4096.0;
    double dist2 = 0;
    for (int k = 0; k < 3; ++k) dist2 += std::pow(xa[k] + u * (xb[k] - xa[k]), 2);
    best = std::min(best, std::sqrt(dist2) / (a.r + u * (b->r - a.r)) - 1.0);
  }
  return best;
}

// later: the shapes' second time step (motion blur, rays at random times), or null.
void expectShapesMatchEmbree(const ShapeScene& start, const ShapeScene* later) {
  const LoadedLibraries& libs = libraries();
  RTCScene reference = commit(*libs.embree, libs.embreeDevice, start, later);
  RTCScene candidate = commit(*libs.obvh, libs.obvhDevice, start, later);
  ASSERT_EQ(libs.obvh->rtcGetDeviceError(libs.obvhDevice), RTC_ERROR_NONE);
  const ShapeScene& data = start;

  std::vector<RTCRay> rays = tools::randomRays(tools::SceneBox{{-1.f, -1.f, -1.f}, {41.f, 25.f, 3.f}}, 100000, 11);
  // Plus rays aimed near every primitive, from random directions.
  std::mt19937 rng(12);
  std::uniform_real_distribution<float> unit(-1.f, 1.f);
  const auto aimAt = [&](float x, float y, float z, float spread, float back = 6.f) {
    for (int k = 0; k < 40; ++k) {
      const float target[3] = {x + spread * unit(rng), y + spread * unit(rng), z + spread * unit(rng)};
      const float dir[3] = {unit(rng), unit(rng), unit(rng) - 1.5f};
      const float org[3] = {target[0] - back * dir[0], target[1] - back * dir[1], target[2] - back * dir[2]};
      RTCRay r{};
      r.org_x = org[0], r.org_y = org[1], r.org_z = org[2], r.dir_x = dir[0], r.dir_y = dir[1], r.dir_z = dir[2];
      r.tnear = 0.f, r.tfar = INFINITY, r.mask = 0xFFFFFFFFu;
      rays.push_back(r);
    }
  };
  for (const Point4& s : data.spheres) aimAt(s.x, s.y, s.z, s.r);
  for (uint32_t first : data.segments) {
    const Point4& a = data.curveVertices[first];
    const Point4& b = data.curveVertices[first + 1];
    aimAt(0.5f * (a.x + b.x), 0.5f * (a.y + b.y), 0.5f * (a.z + b.z), 0.2f);
    // Rays starting near the ribbon: Embree skips hits closer than twice the radius.
    aimAt(0.5f * (a.x + b.x), 0.5f * (a.y + b.y), 0.5f * (a.z + b.z), 0.05f, 0.1f + 0.2f * float(first % 3));
  }

  if (later) assignRandomTimes(rays, 13);
  ShapeAnswerRules rules;
  // Grazing: the answered primitive has the ray within 1e-4 (spheres) or 1e-3 (ribbons) of its outline.
  rules.grazes = [&](const RTCRay& ray, const RTCHit& h) {
    const ShapeScene placed = sceneAt(start, later, ray.time);  // where the shapes are for this ray
    if (h.geomID == 0) return std::fabs(silhouetteMargin(ray, placed.spheres[h.primID], nullptr)) < 1e-4;
    const uint32_t first = data.segments[h.primID];
    return std::fabs(silhouetteMargin(ray, placed.curveVertices[first], &placed.curveVertices[first + 1])) < 1e-3;
  };
  // A ray through the joint of two consecutive segments hits both at the same depth (u = 1 on
  // the first, u = 0 on the second): either is right, and the traversal order picks one.
  rules.jointTie = [&](const RTCRayHit& embree, const RTCRayHit& obvh) {
    const RTCHit &e = embree.hit, &o = obvh.hit;
    const float te = embree.ray.tfar, to = obvh.ray.tfar;
    if (e.geomID != 1 || o.geomID != 1 || std::fabs(te - to) > 1e-5f * std::max(1.f, te)) return false;
    const RTCHit& first = e.primID < o.primID ? e : o;
    const RTCHit& second = e.primID < o.primID ? o : e;
    return data.segments[second.primID] == data.segments[first.primID] + 1 && first.u == 1.f && second.u == 0.f;
  };
  rules.uTolerance = 2e-3f;
  expectSameShapeAnswers(later ? "moving shapes" : "shapes", compareShapeAnswers(reference, candidate, rays, rules),
                         rays.size(), rays.size() / 10);
  libs.embree->rtcReleaseScene(reference);
  libs.obvh->rtcReleaseScene(candidate);
}

TEST(CrossvalShapes, SpheresAndFlatLinearCurvesMatchEmbree) { expectShapesMatchEmbree(makeScene(7), nullptr); }

// Motion blur: two time steps, rays at random times.
TEST(CrossvalShapes, MovingSpheresAndCurvesMatchEmbree) {
  const ShapeScene start = makeScene(7), later = movedOn(start);
  expectShapesMatchEmbree(start, &later);
}

// Embree's point queries call back for none of them, whatever the radius.
TEST(CrossvalShapes, PointQueriesSkipThemAsEmbreeDoes) {
  const LoadedLibraries& libs = libraries();
  const ShapeScene data = makeScene(8);
  const RtcLibrary* lib[2] = {libs.embree, libs.obvh};
  RTCDevice devices[2] = {libs.embreeDevice, libs.obvhDevice};
  unsigned calls[2] = {0, 0};
  for (int k = 0; k < 2; ++k) {
    RTCScene scene = commit(*lib[k], devices[k], data);
    RTCPointQuery query{10.f, 10.f, 1.f, 0.f, INFINITY};
    RTCPointQueryContext context;
    rtcInitPointQueryContext(&context);
    lib[k]->rtcPointQuery(scene, &query, &context, [](RTCPointQueryFunctionArguments* args) {
      ++*static_cast<unsigned*>(args->userPtr);
      return false;
    }, &calls[k]);
    EXPECT_EQ(lib[k]->rtcGetDeviceError(devices[k]), RTC_ERROR_NONE);
    lib[k]->rtcReleaseScene(scene);
  }
  EXPECT_EQ(calls[0], 0u);
  EXPECT_EQ(calls[1], calls[0]);
}

// Embree's buffer rules for the two types: float4 vertices, uint segment indices, no index
// buffer on points.
TEST(CrossvalShapes, BufferFormatErrorsMatchEmbree) {
  const LoadedLibraries& libs = libraries();
  const RtcLibrary* lib[2] = {libs.embree, libs.obvh};
  RTCDevice devices[2] = {libs.embreeDevice, libs.obvhDevice};
  RTCError errors[2][3];
  for (int k = 0; k < 2; ++k) {
    RTCGeometry points = lib[k]->rtcNewGeometry(devices[k], RTC_GEOMETRY_TYPE_SPHERE_POINT);
    lib[k]->rtcSetNewGeometryBuffer(points, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 12, 4);
    errors[k][0] = lib[k]->rtcGetDeviceError(devices[k]);
    lib[k]->rtcSetNewGeometryBuffer(points, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT, 4, 4);
    errors[k][1] = lib[k]->rtcGetDeviceError(devices[k]);
    RTCGeometry curves = lib[k]->rtcNewGeometry(devices[k], RTC_GEOMETRY_TYPE_FLAT_LINEAR_CURVE);
    lib[k]->rtcSetNewGeometryBuffer(curves, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT2, 8, 4);
    errors[k][2] = lib[k]->rtcGetDeviceError(devices[k]);
    lib[k]->rtcReleaseGeometry(points);
    lib[k]->rtcReleaseGeometry(curves);
  }
  for (int e = 0; e < 3; ++e) {
    EXPECT_NE(errors[0][e], RTC_ERROR_NONE) << "case " << e;
    EXPECT_EQ(errors[0][e], errors[1][e]) << "case " << e;
  }
}

}  // namespace
}  // namespace obvh::test
