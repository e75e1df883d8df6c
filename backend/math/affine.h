// Affine transform x' = L x + p, as used by instances.
#pragma once

#include <cmath>
#include <limits>

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

  Box3f xfmBounds(const Box3f& b) const;
};

// The same in double precision: instances keep their world-to-local transform in double so a ray
// picks up only one float rounding when it enters an instance.
struct Affine3d {
  double l[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};  // l[row][col]
  double p[3] = {0, 0, 0};

  static Affine3d inverseOf(const Affine3f& a) {
    const double m[3][3] = {{a.vx.x, a.vy.x, a.vz.x}, {a.vx.y, a.vy.y, a.vz.y}, {a.vx.z, a.vy.z, a.vz.z}};
    const double det = m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) -
                       m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
                       m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
    const double s = 1.0 / det;  // singular: non-finite entries, and transformed rays hit nothing
    Affine3d inv;
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) {
        const int r1 = (c + 1) % 3, r2 = (c + 2) % 3, c1 = (r + 1) % 3, c2 = (r + 2) % 3;
        inv.l[r][c] = (m[r1][c1] * m[r2][c2] - m[r1][c2] * m[r2][c1]) * s;
      }
    const double t[3] = {a.p.x, a.p.y, a.p.z};
    for (int r = 0; r < 3; ++r) inv.p[r] = -(inv.l[r][0] * t[0] + inv.l[r][1] * t[1] + inv.l[r][2] * t[2]);
    return inv;
  }

  Vec3f xfmVector(const Vec3f& v) const {
    return {float(l[0][0] * v.x + l[0][1] * v.y + l[0][2] * v.z), float(l[1][0] * v.x + l[1][1] * v.y + l[1][2] * v.z),
            float(l[2][0] * v.x + l[2][1] * v.y + l[2][2] * v.z)};
  }
  Vec3f xfmPoint(const Vec3f& v) const {
    return {float(l[0][0] * v.x + l[0][1] * v.y + l[0][2] * v.z + p[0]),
            float(l[1][0] * v.x + l[1][1] * v.y + l[1][2] * v.z + p[1]),
            float(l[2][0] * v.x + l[2][1] * v.y + l[2][2] * v.z + p[2])};
  }
};

// Padded by a few ulps: the corners are transformed in float, and a box that rounding shrank
// could cull rays that hit the instanced geometry.
inline Box3f Affine3f::xfmBounds(const Box3f& b) const {
  Box3f out;
  if (b.empty()) return out;
  for (int corner = 0; corner < 8; ++corner)
    out.extend(xfmPoint({corner & 1 ? b.upper.x : b.lower.x, corner & 2 ? b.upper.y : b.lower.y,
                         corner & 4 ? b.upper.z : b.lower.z}));
  for (int axis = 0; axis < 3; ++axis) {
    const float pad = 8.f * std::numeric_limits<float>::epsilon() *
                      std::max(std::fabs(out.lower[axis]), std::fabs(out.upper[axis]));
    out.lower[axis] -= pad;
    out.upper[axis] += pad;
  }
  return out;
}

}  // namespace obvh
