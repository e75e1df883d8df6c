#include "scene/instance_motion.h"

#include <algorithm>
#include <cmath>

#include "scene/time_segment.h"

namespace obvh {
namespace {

Affine3f scaleSkewShift(const QuaternionDecomposition& d) {
  Affine3f s;
  s.vx = {d.scale.x, 0.f, 0.f};
  s.vy = {d.skewXY, d.scale.y, 0.f};
  s.vz = {d.skewXZ, d.skewYZ, d.scale.z};
  s.p = d.shift;
  return s;
}

float lerp(float a, float b, float f) { return a * (1.f - f) + b * f; }
Vec3f lerp(const Vec3f& a, const Vec3f& b, float f) { return a * (1.f - f) + b * f; }

// The quaternions' spherical interpolation along the shorter arc; nearly equal ones are blended
// linearly and normalized (Embree's threshold).
// The quaternion of a decomposition scaled to unit length.
QuaternionDecomposition unitQuaternion(QuaternionDecomposition d) {
  const float norm = std::sqrt(d.r * d.r + d.i * d.i + d.j * d.j + d.k * d.k);
  d.r /= norm, d.i /= norm, d.j /= norm, d.k /= norm;
  return d;
}

void slerp(QuaternionDecomposition a, QuaternionDecomposition b, float f, QuaternionDecomposition& out) {
  a = unitQuaternion(a), b = unitQuaternion(b);
  float cosTheta = a.r * b.r + a.i * b.i + a.j * b.j + a.k * b.k;
  if (cosTheta < 0.f) {
    cosTheta = -cosTheta;
    b.r = -b.r, b.i = -b.i, b.j = -b.j, b.k = -b.k;
  }
  if (cosTheta > 0.9995f) {
    out.r = lerp(a.r, b.r, f), out.i = lerp(a.i, b.i, f), out.j = lerp(a.j, b.j, f), out.k = lerp(a.k, b.k, f);
    return;  // compose() normalizes
  }
  // q = cos(phi) a + sin(phi) p, p the unit quaternion orthogonal to a in the plane of a and b.
  const float phi = f * std::acos(std::min(cosTheta, 1.f));
  float pr = b.r - cosTheta * a.r, pi = b.i - cosTheta * a.i, pj = b.j - cosTheta * a.j, pk = b.k - cosTheta * a.k;
  const float norm = std::sqrt(pr * pr + pi * pi + pj * pj + pk * pk);
  pr /= norm, pi /= norm, pj /= norm, pk /= norm;
  const float c = std::cos(phi), s = std::sin(phi);
  out.r = c * a.r + s * pr, out.i = c * a.i + s * pi, out.j = c * a.j + s * pj, out.k = c * a.k + s * pk;
}

}  // namespace

bool QuaternionDecomposition::compose(Affine3f& out) const {
  const float norm = std::sqrt(r * r + i * i + j * j + k * k);
  if (!(norm > 0.f) || !std::isfinite(norm)) return false;
  const float qr = r / norm, qi = i / norm, qj = j / norm, qk = k / norm;
  Affine3f rot;
  rot.vx = {1 - 2 * (qj * qj + qk * qk), 2 * (qi * qj + qr * qk), 2 * (qi * qk - qr * qj)};
  rot.vy = {2 * (qi * qj - qr * qk), 1 - 2 * (qi * qi + qk * qk), 2 * (qj * qk + qr * qi)};
  rot.vz = {2 * (qi * qk + qr * qj), 2 * (qj * qk - qr * qi), 1 - 2 * (qi * qi + qj * qj)};
  const Affine3f s = scaleSkewShift(*this);
  out.vx = rot.xfmVector(s.vx);
  out.vy = rot.xfmVector(s.vy);
  out.vz = rot.xfmVector(s.vz);
  out.p = rot.xfmVector(s.p) + translation;
  return true;
}

bool InstanceMotion::at(float time, Affine3f& localToWorld) const {
  TimeSegment s;
  if (!timeSegment(time, timeStart, timeEnd, uint32_t(steps.size()), s)) return false;
  const size_t segment = size_t(s.segment);
  const float f = s.f;
  if (quaternions.size() == steps.size()) {
    const QuaternionDecomposition& a = quaternions[segment];
    const QuaternionDecomposition& b = quaternions[segment + 1];
    QuaternionDecomposition blend;
    blend.scale = lerp(a.scale, b.scale, f);
    blend.skewXY = lerp(a.skewXY, b.skewXY, f), blend.skewXZ = lerp(a.skewXZ, b.skewXZ, f);
    blend.skewYZ = lerp(a.skewYZ, b.skewYZ, f);
    blend.shift = lerp(a.shift, b.shift, f);
    blend.translation = lerp(a.translation, b.translation, f);
    slerp(a, b, f, blend);
    return blend.compose(localToWorld);
  }
  const Affine3f& a = steps[segment];
  const Affine3f& b = steps[segment + 1];
  localToWorld.vx = lerp(a.vx, b.vx, f);
  localToWorld.vy = lerp(a.vy, b.vy, f);
  localToWorld.vz = lerp(a.vz, b.vz, f);
  localToWorld.p = lerp(a.p, b.p, f);
  return true;
}

Box3f InstanceMotion::bounds(const Box3f& child) const {
  Box3f box;
  if (quaternions.size() != steps.size()) {
    // A blend of two transforms maps a point between its images under both.
    for (const Affine3f& step : steps) box.extend(step.xfmBounds(child));
    return box;
  }
  // T + R S p: S blends linearly, so |S p| stays below its largest value at the steps (over the
  // box's corners), R keeps lengths, and T moves along the segments between the translations.
  float radius = 0.f;
  for (const QuaternionDecomposition& d : quaternions) {
    const Affine3f s = scaleSkewShift(d);
    for (int corner = 0; corner < 8; ++corner) {
      const Vec3f p{corner & 1 ? child.upper.x : child.lower.x, corner & 2 ? child.upper.y : child.lower.y,
                    corner & 4 ? child.upper.z : child.lower.z};
      const Vec3f q = s.xfmPoint(p);
      radius = std::max(radius, std::sqrt(q.x * q.x + q.y * q.y + q.z * q.z));
    }
  }
  radius *= 1.0001f;  // rounding of the rotation
  for (const QuaternionDecomposition& d : quaternions) {
    box.extend(d.translation - Vec3f{radius, radius, radius});
    box.extend(d.translation + Vec3f{radius, radius, radius});
  }
  return box;
}

}  // namespace obvh
