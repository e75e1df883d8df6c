// Watertight ray/triangle test after Woop, Benthin and Wald (JCGT 2013).
// Rays that pass exactly through a shared edge or vertex hit at least one of the adjacent
// triangles: the edge functions are evaluated in a ray-aligned frame, with a double-precision
// fallback when one of them rounds to zero.
#pragma once

#include <cmath>

#include "intersect/ray.h"
#include "intersect/triangle.h"

namespace obvh {

// The axes kx, ky that go with the dominant axis kz, by kz * 2 + (dir[kz] < 0): (kz + 1) % 3 and
// (kx + 1) % 3, swapped for a negative dominant component (see WatertightRay's constructor).
struct WatertightAxisPair {
  int kx, ky;
};
inline constexpr WatertightAxisPair kWatertightOtherAxes[6] = {{1, 2}, {2, 1}, {2, 0}, {0, 2}, {0, 1}, {1, 0}};

// Per-ray constants of the shear transform, computed once per ray.
// The fields' order is the one watertightFramesOfLanes (watertight_lanes.h) writes a lane group's
// frames in: the first eight words (the floats and kz) by a transposed store, then kx and ky as one
// pair.
struct WatertightRay {
  float Sx = 0.f, Sy = 0.f, Sz = 1.f;
  Vec3f org;
  // tnear * |dir[kz]|: the start of the segment as a distance along kz, with which the block tests
  // drop in float the candidates that certainly lie before it (certainlyBeforeNearLanes).
  float nearAlongKz = 0.f;
  int kz = 2, kx = 0, ky = 1;

  WatertightRay() = default;
  // Always inlined: a kernel whose inliner budget ran out called the one copy the linker keeps,
  // compiled for baseline x86-64 (54 instructions a ray on the grid probe).
  [[gnu::always_inline]] explicit WatertightRay(const Ray& ray) : org(ray.org) {
    const float ax = std::fabs(ray.dir.x), ay = std::fabs(ray.dir.y), az = std::fabs(ray.dir.z);
    kz = (ax >= ay && ax >= az) ? 0 : (ay >= az ? 1 : 2);
    kx = (kz + 1) % 3;
    ky = (kx + 1) % 3;
    // Swapping kx and ky when the dominant component is negative keeps the winding (and the sign
    // of the edge functions) independent of the ray direction.
    if (ray.dir[kz] < 0.f) {
      const int t = kx;
      kx = ky;
      ky = t;
    }
    shearAlongAxes(ray);
    nearAlongKz = ray.tnear * std::fabs(ray.dir[kz]);
  }

  // The same constants with the axes chosen by arithmetic on the comparisons instead of branches:
  // which axis dominates is as unpredictable as an incoherent ray's direction (callgrind's branch
  // simulation put 0.85 mispredicted branches a diffuse bounce on the bunny there). For walks that
  // make the constants while their first node tests run (walkWideTree's onEntering), where the
  // arithmetic's longer chain is hidden; made at a leaf that waits for them, the branches guessed
  // right for camera rays were faster.
  [[gnu::always_inline]] static WatertightRay withoutBranches(const Ray& ray) {
    WatertightRay w;
    w.org = ray.org;
    const float ax = std::fabs(ray.dir.x), ay = std::fabs(ray.dir.y), az = std::fabs(ray.dir.z);
    const int xBeatsY = ax >= ay, xBeatsZ = ax >= az, yBeatsZ = ay >= az;
    const int kz = (1 - (xBeatsY & xBeatsZ)) * (2 - yBeatsZ);
    const float dominant = ray.dir[kz];
    // kx and ky read from a table by kz and the dominant component's sign: the constructor's
    // (kz + 1) % 3, (kx + 1) % 3 and swap. Computed (a table of next axes, then a swap by exclusive
    // or), GCC kept the swap in vector registers: the set-up took 59 instructions, now 50
    // (callgrind, bunny: 9 fewer a camera ray that hits and a diffuse bounce). A table of bytes took
    // 2 more than this one of ints.
    const WatertightAxisPair other = kWatertightOtherAxes[kz * 2 + int(dominant < 0.f)];
    w.kx = other.kx;
    w.ky = other.ky;
    w.kz = kz;
    w.Sx = ray.dir[other.kx] / dominant;
    w.Sy = ray.dir[other.ky] / dominant;
    w.Sz = 1.f / dominant;
    w.nearAlongKz = ray.tnear * std::fabs(dominant);
    return w;
  }

 private:
  // The shear constants for the axis order (kx, ky, kz) already chosen.
  [[gnu::always_inline]] void shearAlongAxes(const Ray& ray) {
    Sx = ray.dir[kx] / ray.dir[kz];
    Sy = ray.dir[ky] / ray.dir[kz];
    Sz = 1.f / ray.dir[kz];
  }
};

struct TriangleHit {
  float t, u, v;
};

// The ray's hit on the plane of (v0, v1, v2) in double precision, from the triangle's own edges
// (Moeller-Trumbore's formulas): det == 0 for a degenerate triangle, else t and the weights u, v
// of v1 and v2. D is double, or four lanes of double (simd/double_lanes.h) for four triangles at
// once, each lane computing exactly what the scalar version computes.
template <typename D>
struct DoublePlaneHit {
  D det, t, u, v;
};

// Always inlined: as a call (GCC kept the AVX2 kernels' copy out of line, the shared header being
// outside their target region) it sat in the middle of the lanes' double-precision test, whose live
// vector registers it clobbered and which were spilled around it.
template <typename D>
[[gnu::always_inline]] inline D broadcastDouble(double x) {
  return D::broadcast(x);
}
template <>
inline double broadcastDouble<double>(double x) {
  return x;
}

template <typename D>
[[gnu::always_inline]] inline DoublePlaneHit<D> planeHitInDouble(const D org[3], const D dir[3], const D v0[3],
                                                                 const D v1[3], const D v2[3]) {
  D e1[3], e2[3], s[3];
  for (int a = 0; a < 3; ++a) {
    e1[a] = v1[a] - v0[a];
    e2[a] = v2[a] - v0[a];
    s[a] = org[a] - v0[a];
  }
  const D p[3] = {dir[1] * e2[2] - dir[2] * e2[1], dir[2] * e2[0] - dir[0] * e2[2], dir[0] * e2[1] - dir[1] * e2[0]};
  const D q[3] = {s[1] * e1[2] - s[2] * e1[1], s[2] * e1[0] - s[0] * e1[2], s[0] * e1[1] - s[1] * e1[0]};
  DoublePlaneHit<D> h;
  h.det = e1[0] * p[0] + e1[1] * p[1] + e1[2] * p[2];
  const D rcpDet = broadcastDouble<D>(1.0) / h.det;
  h.t = (e2[0] * q[0] + e2[1] * q[1] + e2[2] * q[2]) * rcpDet;
  h.u = (s[0] * p[0] + s[1] * p[1] + s[2] * p[2]) * rcpDet;
  h.v = (dir[0] * q[0] + dir[1] * q[1] + dir[2] * q[2]) * rcpDet;
  return h;
}

// A degenerate triangle (zero edge determinant) that passed the edge functions: the sheared
// frame's values are kept rather than the hit dropped.
template <typename Vertex>
inline bool resolveDegenerateHit(const WatertightRay& wr, const Ray& ray, Vertex&& vertex, float U, float V, float W,
                                 TriangleHit& out) {
  const float Az = wr.Sz * (vertex(0, wr.kz) - wr.org[wr.kz]);
  const float Bz = wr.Sz * (vertex(1, wr.kz) - wr.org[wr.kz]);
  const float Cz = wr.Sz * (vertex(2, wr.kz) - wr.org[wr.kz]);
  const float rcpDet = 1.f / (U + V + W);
  const float t = (U * Az + V * Bz + W * Cz) * rcpDet;
  if (!(t > ray.tnear && t <= ray.tfar)) return false;
  // U weighs v0, V weighs v1 and W weighs v2; Embree's u and v are the weights of v1 and v2.
  out = {t, V * rcpDet, W * rcpDet};
  return true;
}

// The end of the test, once the edge functions U, V, W (weights of v0, v1, v2 in the sheared frame,
// no mixed signs) and the plane hit in double precision (t, u, v rounded to float; `degenerate`
// when its determinant is zero) are known: rejects det == 0 and a distance outside the segment.
// The SIMD kernels compute the plane hits of a block's four triangles at once and end each lane here.
template <typename Vertex>
[[gnu::always_inline]] inline bool finishWatertightHit(const WatertightRay& frame, const Ray& ray, Vertex&& vertex, float U,
                                                       float V, float W, bool degenerate, float t, float u, float v,
                                                       TriangleHit& out) {
  if (!(U + V + W != 0.f)) return false;  // also rejects NaN
  if (degenerate) return resolveDegenerateHit(frame, ray, vertex, U, V, W, out);
  if (!(t > ray.tnear && t <= ray.tfar)) return false;
  out = {t, u, v};
  return true;
}

// Second half of the test for one triangle. vertex(k, axis) returns a coordinate of v0, v1 or v2
// as a float.
// The edge functions decide whether the ray hits (that is what makes the test watertight), but in
// single precision the shear loses accuracy for small triangles far from the ray origin and for
// grazing rays. Distance and barycentrics of an accepted candidate are therefore computed in
// double precision from the triangle's own edges (per accepted candidate, not per test).
template <typename Vertex>
[[gnu::always_inline]] inline bool resolveWatertightHitOf(const WatertightRay& frame, const Ray& ray, Vertex&& vertex, float U,
                                                          float V, float W, TriangleHit& out) {
  const double org[3] = {ray.org.x, ray.org.y, ray.org.z}, dir[3] = {ray.dir.x, ray.dir.y, ray.dir.z};
  double v[3][3];
  for (int k = 0; k < 3; ++k)
    for (int a = 0; a < 3; ++a) v[k][a] = vertex(k, a);
  const DoublePlaneHit<double> h = planeHitInDouble(org, dir, v[0], v[1], v[2]);
  return finishWatertightHit(frame, ray, vertex, U, V, W, h.det == 0.0, float(h.t), float(h.u), float(h.v), out);
}

[[gnu::always_inline]] inline bool resolveWatertightHit(const WatertightRay& frame, const Ray& ray, const Vec3f& v0,
                                                        const Vec3f& v1, const Vec3f& v2, float U, float V, float W,
                                                        TriangleHit& out) {
  const Vec3f* vertices[3] = {&v0, &v1, &v2};
  return resolveWatertightHitOf(frame, ray, [&](int k, int axis) { return (*vertices[k])[axis]; }, U, V, W, out);
}

// Returns true and fills out when the ray hits the triangle with tnear < t <= tfar.
inline bool intersectWatertight(const WatertightRay& wr, const Ray& ray, const Vec3f& v0, const Vec3f& v1,
                                const Vec3f& v2, TriangleHit& out) {
  const Vec3f A = v0 - wr.org, B = v1 - wr.org, C = v2 - wr.org;
  const float Ax = A[wr.kx] - wr.Sx * A[wr.kz], Ay = A[wr.ky] - wr.Sy * A[wr.kz];
  const float Bx = B[wr.kx] - wr.Sx * B[wr.kz], By = B[wr.ky] - wr.Sy * B[wr.kz];
  const float Cx = C[wr.kx] - wr.Sx * C[wr.kz], Cy = C[wr.ky] - wr.Sy * C[wr.kz];

  float U = Cx * By - Cy * Bx;
  float V = Ax * Cy - Ay * Cx;
  float W = Bx * Ay - By * Ax;
  if (U == 0.f || V == 0.f || W == 0.f) {
    U = float(double(Cx) * double(By) - double(Cy) * double(Bx));
    V = float(double(Ax) * double(Cy) - double(Ay) * double(Cx));
    W = float(double(Bx) * double(Ay) - double(By) * double(Ax));
  }
  if ((U < 0.f || V < 0.f || W < 0.f) && (U > 0.f || V > 0.f || W > 0.f)) return false;
  return resolveWatertightHit(wr, ray, v0, v1, v2, U, V, W, out);
}

// Embree's geometry normal: cross(v2 - v0, v0 - v1), unnormalized.
inline Vec3f embreeGeometryNormal(const Vec3f& v0, const Vec3f& v1, const Vec3f& v2) {
  return cross(v2 - v0, v0 - v1);
}

}  // namespace obvh
