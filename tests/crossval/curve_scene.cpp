#include "curve_scene.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <random>

#include "ray_generation.h"

namespace obvh::test {
namespace {

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

}  // namespace

const BasisWeights kBasisWeights[3] = {bezierWeights, bsplineWeights, catmullRomWeights};

namespace {

// The largest radius times curvature along the segment whose control vertices are c (sampled).
// Where it reaches 1 the tube overlaps itself, and its circles no longer make one surface: obvh
// and Embree then answer differently (each finds some of the overlapping walls), so the scene
// keeps well clear of that, as hair and fibres do.
double largestBend(BasisWeights weights, const Point4* c) {
  double worst = 0.0;
  const auto derivative = [&](double u, double out[3], double& r) {
    double w[4], dw[4];
    weights(u, w, dw);
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

}  // namespace

CurveScene makeCurveScene(uint32_t seed) {
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
      } while (largestBend(kBasisWeights[b], &curve[0]) > 0.5 || largestBend(kBasisWeights[b], &curve[b == 0 ? 3 : 1]) > 0.5);
      const uint32_t first = uint32_t(scene.vertices[b].size());
      scene.vertices[b].insert(scene.vertices[b].end(), curve.begin(), curve.end());
      scene.segments[b].push_back(first);
      scene.segments[b].push_back(first + (b == 0 ? 3 : 1));
    }
  return scene;
}

CurveScene movedOn(CurveScene scene) {
  for (std::vector<Point4>& points : scene.vertices)
    for (Point4& p : points) p.x += 0.5f, p.z -= 0.3f, p.r *= 1.2f;
  return scene;
}

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

RTCScene commitCurveScene(const RtcLibrary& lib, RTCDevice device, const CurveScene& data, const CurveScene* later,
                          const RTCGeometryType types[3], float tessellationRate) {
  RTCScene scene = lib.rtcNewScene(device);
  for (int b = 0; b < 3; ++b) {
    RTCGeometry g = lib.rtcNewGeometry(device, types[b]);
    if (tessellationRate >= 0.f) lib.rtcSetGeometryTessellationRate(g, tessellationRate);
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

std::vector<RTCRay> raysAtCurves(const CurveScene& data, const CurveScene* later) {
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
        kBasisWeights[b](0.5 + 0.55 * double(unit(rng)), w, dw);  // a little past the ends too
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

  return rays;
}

RTCScene commitHermiteCurveScene(const RtcLibrary& lib, RTCDevice device, const CurveScene& data,
                                 const CurveScene* later, RTCGeometryType type, float tessellationRate) {
  RTCScene scene = lib.rtcNewScene(device);
  RTCGeometry g = lib.rtcNewGeometry(device, type);
  if (tessellationRate >= 0.f) lib.rtcSetGeometryTessellationRate(g, tessellationRate);
  const size_t segments = data.segments[0].size();
  if (later) lib.rtcSetGeometryTimeStepCount(g, 2);
  for (unsigned step = 0; step < (later ? 2u : 1u); ++step) {
    const std::vector<Point4>& bezier = step == 0 ? data.vertices[0] : later->vertices[0];
    auto* v = static_cast<Point4*>(
        lib.rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, step, RTC_FORMAT_FLOAT4, 16, 2 * segments));
    auto* t = static_cast<Point4*>(
        lib.rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_TANGENT, step, RTC_FORMAT_FLOAT4, 16, 2 * segments));
    const auto slope = [](const Point4& from, const Point4& to) {
      return Point4{3.f * (to.x - from.x), 3.f * (to.y - from.y), 3.f * (to.z - from.z), 3.f * (to.r - from.r)};
    };
    for (size_t k = 0; k < segments; ++k) {
      const Point4* c = &bezier[data.segments[0][k]];
      v[2 * k] = c[0], v[2 * k + 1] = c[3];
      t[2 * k] = slope(c[0], c[1]), t[2 * k + 1] = slope(c[2], c[3]);
    }
  }
  auto* index = static_cast<uint32_t*>(
      lib.rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT, 4, segments));
  for (size_t k = 0; k < segments; ++k) index[k] = uint32_t(2 * k);
  lib.rtcCommitGeometry(g);
  lib.rtcAttachGeometry(scene, g);
  lib.rtcReleaseGeometry(g);
  lib.rtcCommitScene(scene);
  return scene;
}

bool cubicJointTie(const RTCRayHit& embree, const RTCRayHit& obvh) {
  const RTCHit &e = embree.hit, &o = obvh.hit;
  if (e.geomID != o.geomID || e.geomID == RTC_INVALID_GEOMETRY_ID || e.primID / 2 != o.primID / 2) return false;
  const float te = embree.ray.tfar, to = obvh.ray.tfar;
  const RTCHit& first = e.primID < o.primID ? e : o;
  const RTCHit& second = e.primID < o.primID ? o : e;
  return std::fabs(te - to) <= 1e-3f * std::max(1.f, te) && first.u > 0.99f && second.u < 0.01f;
}

CurvePoint evaluateCurve(int basis, const Point4* control, double u) {
  double w[4], dw[4];
  kBasisWeights[basis](u, w, dw);
  CurvePoint e{};
  for (int k = 0; k < 4; ++k) {
    const double c[3] = {control[k].x, control[k].y, control[k].z};
    for (int a = 0; a < 3; ++a) e.p[a] += w[k] * c[a], e.dp[a] += dw[k] * c[a];
    e.r += w[k] * control[k].r;
  }
  return e;
}

}  // namespace obvh::test
