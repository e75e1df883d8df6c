// Spheres (Embree's RTC_GEOMETRY_TYPE_SPHERE_POINT) and flat linear curve segments
// (RTC_GEOMETRY_TYPE_FLAT_LINEAR_CURVE), tested in double precision with Embree's hit
// conventions (the cross-validation compares them with Embree's answers):
// - a sphere is hit at the nearer root of the ray inside [tnear, tfar], else the farther one
//   (rays starting inside see the far side); Ng = hit point - centre, u = v = 0;
// - a flat curve segment is a ribbon that always faces the ray: seen along the ray, the point of
//   the segment nearest to the ray (u, clamped to the segment) is hit when the ray passes within
//   the radius interpolated there, at the depth of that point; Ng = v1 - v0 (the tangent), v = 0;
//   a hit closer to the ray origin than twice that radius is skipped (Debian's build avoids a
//   ribbon's self-intersection so; measured: |d| does not matter, spheres have no such rule).
#pragma once

#include <algorithm>
#include <cmath>

#include "intersect/ray.h"
#include "math/vec3.h"

namespace obvh {

// A point of a curve or a sphere: position and radius (Embree's RTC_FORMAT_FLOAT4 vertices).
struct ShapeVertex {
  Vec3f p;
  float r = 0.f;
};

struct ShapeHit {
  float t = 0.f, u = 0.f, v = 0.f;
  Vec3f Ng;
};

inline Box3f sphereBounds(const ShapeVertex& s) {
  const float r = std::fabs(s.r);
  Box3f b;
  b.extend(s.p - Vec3f{r, r, r});
  b.extend(s.p + Vec3f{r, r, r});
  return b;
}

inline Box3f segmentBounds(const ShapeVertex& a, const ShapeVertex& b) {
  const float r = std::max(std::fabs(a.r), std::fabs(b.r));
  Box3f box;
  box.extend(a.p - Vec3f{r, r, r});
  box.extend(a.p + Vec3f{r, r, r});
  box.extend(b.p - Vec3f{r, r, r});
  box.extend(b.p + Vec3f{r, r, r});
  return box;
}

inline bool intersectSphere(const Ray& ray, const ShapeVertex& s, ShapeHit& hit) {
  double o[3], d[3];
  for (int k = 0; k < 3; ++k) o[k] = double(ray.org[k]) - double(s.p[k]), d[k] = double(ray.dir[k]);
  const double a = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
  const double b = o[0] * d[0] + o[1] * d[1] + o[2] * d[2];
  const double c = o[0] * o[0] + o[1] * o[1] + o[2] * o[2] - double(s.r) * double(s.r);
  const double discriminant = b * b - a * c;
  if (!(a > 0.0) || !(discriminant >= 0.0)) return false;
  const double root = std::sqrt(discriminant);
  // The two roots without cancellation: q has the sign of -b.
  const double q = b > 0.0 ? -(b + root) : -(b - root);
  double t0 = q / a, t1 = q != 0.0 ? c / q : t0;
  if (t0 > t1) std::swap(t0, t1);
  double t = t0;
  if (!(t >= double(ray.tnear) && t <= double(ray.tfar))) t = t1;
  if (!(t >= double(ray.tnear) && t <= double(ray.tfar))) return false;
  hit.t = float(t);
  hit.u = 0.f;
  hit.Ng = {float(o[0] + t * d[0]), float(o[1] + t * d[1]), float(o[2] + t * d[2])};
  return true;
}

inline bool intersectFlatSegment(const Ray& ray, const ShapeVertex& v0, const ShapeVertex& v1, ShapeHit& hit) {
  double d[3], q0[3], q1[3];
  double length2 = 0.0;
  for (int k = 0; k < 3; ++k) {
    d[k] = double(ray.dir[k]);
    length2 += d[k] * d[k];
    q0[k] = double(v0.p[k]) - double(ray.org[k]);
    q1[k] = double(v1.p[k]) - double(ray.org[k]);
  }
  if (!(length2 > 0.0)) return false;
  // Depth along the ray (in units of t) and the offset across it, for both end points.
  const double z0 = (q0[0] * d[0] + q0[1] * d[1] + q0[2] * d[2]) / length2;
  const double z1 = (q1[0] * d[0] + q1[1] * d[1] + q1[2] * d[2]) / length2;
  double x0[3], x10[3];
  for (int k = 0; k < 3; ++k) {
    x0[k] = q0[k] - z0 * d[k];
    x10[k] = (q1[k] - z1 * d[k]) - x0[k];
  }
  const double along = x10[0] * x10[0] + x10[1] * x10[1] + x10[2] * x10[2];
  double u = along > 0.0 ? -(x0[0] * x10[0] + x0[1] * x10[1] + x0[2] * x10[2]) / along : 0.0;
  u = std::clamp(u, 0.0, 1.0);
  double distance2 = 0.0;
  for (int k = 0; k < 3; ++k) {
    const double x = x0[k] + u * x10[k];
    distance2 += x * x;
  }
  const double radius = double(v0.r) + u * (double(v1.r) - double(v0.r));
  const double t = z0 + u * (z1 - z0);
  if (!(distance2 <= radius * radius) || !(t >= double(ray.tnear) && t <= double(ray.tfar))) return false;
  if (!(t * std::sqrt(length2) > 2.0 * radius)) return false;
  hit.t = float(t);
  hit.u = float(u);
  hit.Ng = v1.p - v0.p;
  return true;
}

}  // namespace obvh
