// Watertight ray/triangle test after Woop, Benthin and Wald (JCGT 2013).
// Rays that pass exactly through a shared edge or vertex hit at least one of the adjacent
// triangles: the edge functions are evaluated in a ray-aligned frame, with a double-precision
// fallback when one of them rounds to zero.
#pragma once

#include <cmath>

#include "intersect/ray.h"
#include "intersect/triangle.h"

namespace obvh {

// Per-ray constants of the shear transform, computed once per ray.
struct WatertightRay {
  int kx = 0, ky = 1, kz = 2;
  float Sx = 0.f, Sy = 0.f, Sz = 1.f;
  Vec3f org;

  WatertightRay() = default;
  explicit WatertightRay(const Ray& ray) : org(ray.org) {
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
    Sx = ray.dir[kx] / ray.dir[kz];
    Sy = ray.dir[ky] / ray.dir[kz];
    Sz = 1.f / ray.dir[kz];
  }
};

struct TriangleHit {
  float t, u, v;
};

// Second half of the test, once the edge functions U, V, W (weights of v0, v1, v2 in the sheared
// frame, no mixed signs) are known: rejects det == 0 and computes t, u, v. Split out so that SIMD
// kernels that evaluate the edge functions of several triangles at once share it. vertex(k, axis)
// returns a coordinate of v0, v1 or v2 as a float; the SIMD kernels read it straight from a lane
// of their triangle block (a copied-out triangle stayed alive across this function, spilled).
template <typename Vertex>
[[gnu::always_inline]] inline bool resolveWatertightHitOf(const WatertightRay& wr, const Ray& ray, Vertex&& vertex,
                                                          float U, float V, float W, TriangleHit& out) {
  const float det = U + V + W;
  if (!(det != 0.f)) return false;  // also rejects NaN

  // The edge functions decide whether the ray hits (that is what makes the test watertight), but
  // in single precision the shear loses accuracy for small triangles far from the ray origin and
  // for grazing rays. Distance and barycentrics of an accepted candidate are therefore recomputed
  // in double precision from the triangle's own edges; this costs a few operations per accepted
  // candidate, not per test.
  const double ox = ray.org.x, oy = ray.org.y, oz = ray.org.z;
  const double dx = ray.dir.x, dy = ray.dir.y, dz = ray.dir.z;
  const double v0x = vertex(0, 0), v0y = vertex(0, 1), v0z = vertex(0, 2);
  const double e1x = double(vertex(1, 0)) - v0x, e1y = double(vertex(1, 1)) - v0y, e1z = double(vertex(1, 2)) - v0z;
  const double e2x = double(vertex(2, 0)) - v0x, e2y = double(vertex(2, 1)) - v0y, e2z = double(vertex(2, 2)) - v0z;
  const double sx = ox - v0x, sy = oy - v0y, sz = oz - v0z;
  const double px = dy * e2z - dz * e2y, py = dz * e2x - dx * e2z, pz = dx * e2y - dy * e2x;
  const double edgeDet = e1x * px + e1y * py + e1z * pz;
  if (edgeDet == 0.0) {
    // Only a degenerate triangle gets here; keep the sheared values rather than drop the hit.
    const float Az = wr.Sz * (vertex(0, wr.kz) - wr.org[wr.kz]);
    const float Bz = wr.Sz * (vertex(1, wr.kz) - wr.org[wr.kz]);
    const float Cz = wr.Sz * (vertex(2, wr.kz) - wr.org[wr.kz]);
    const float rcpDet = 1.f / det;
    const float t = (U * Az + V * Bz + W * Cz) * rcpDet;
    if (!(t > ray.tnear && t <= ray.tfar)) return false;
    // U weighs v0, V weighs v1 and W weighs v2; Embree's u and v are the weights of v1 and v2.
    out = {t, V * rcpDet, W * rcpDet};
    return true;
  }
  const double qx = sy * e1z - sz * e1y, qy = sz * e1x - sx * e1z, qz = sx * e1y - sy * e1x;
  const double rcpEdgeDet = 1.0 / edgeDet;
  const float t = float((e2x * qx + e2y * qy + e2z * qz) * rcpEdgeDet);
  if (!(t > ray.tnear && t <= ray.tfar)) return false;
  out = {t, float((sx * px + sy * py + sz * pz) * rcpEdgeDet), float((dx * qx + dy * qy + dz * qz) * rcpEdgeDet)};
  return true;
}

inline bool resolveWatertightHit(const WatertightRay& wr, const Ray& ray, const Vec3f& v0, const Vec3f& v1,
                                 const Vec3f& v2, float U, float V, float W, TriangleHit& out) {
  const Vec3f* vertices[3] = {&v0, &v1, &v2};
  return resolveWatertightHitOf(wr, ray, [&](int k, int axis) { return (*vertices[k])[axis]; }, U, V, W, out);
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
