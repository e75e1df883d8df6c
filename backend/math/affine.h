// Affine transform x' = L x + p, as used by instances.
#pragma once

#include "math/vec3.h"

namespace obvh {

struct Affine3f {
  Vec3f vx{1.f, 0.f, 0.f}, vy{0.f, 1.f, 0.f}, vz{0.f, 0.f, 1.f};  // columns of L
  Vec3f p{0.f, 0.f, 0.f};

  Vec3f xfmVector(const Vec3f& v) const { return vx * v.x + vy * v.y + vz * v.z; }
  Vec3f xfmPoint(const Vec3f& v) const { return xfmVector(v) + p; }

  // Inverse by the adjugate; a singular transform yields non-finite values, and rays
  // transformed by it hit nothing.
  Affine3f inverse() const {
    const Vec3f r0 = cross(vy, vz), r1 = cross(vz, vx), r2 = cross(vx, vy);
    const float det = dot(vx, r0);
    const float s = 1.f / det;
    Affine3f inv;
    // Rows of L^-1 are r0/det, r1/det, r2/det; store them as columns of the inverse.
    inv.vx = {r0.x * s, r1.x * s, r2.x * s};
    inv.vy = {r0.y * s, r1.y * s, r2.y * s};
    inv.vz = {r0.z * s, r1.z * s, r2.z * s};
    inv.p = inv.xfmVector(p) * -1.f;
    return inv;
  }

  Box3f xfmBounds(const Box3f& b) const {
    Box3f out;
    if (b.empty()) return out;
    for (int corner = 0; corner < 8; ++corner)
      out.extend(xfmPoint({corner & 1 ? b.upper.x : b.lower.x, corner & 2 ? b.upper.y : b.lower.y,
                           corner & 4 ? b.upper.z : b.lower.z}));
    return out;
  }
};

}  // namespace obvh
