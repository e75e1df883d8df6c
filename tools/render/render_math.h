// Small vector, quaternion and 4x4 matrix types for the renderer (glTF conventions: column-major
// matrices, quaternions as x, y, z, w).
#pragma once

#include <algorithm>
#include <array>
#include <cmath>

namespace obvh::render {

struct Vec3 {
  float x = 0.f, y = 0.f, z = 0.f;
  constexpr Vec3() = default;
  constexpr Vec3(float x_, float y_, float z_) : x(x_), y(y_), z(z_) {}
  explicit constexpr Vec3(float s) : x(s), y(s), z(s) {}
  float operator[](int i) const { return i == 0 ? x : (i == 1 ? y : z); }
  float& operator[](int i) { return i == 0 ? x : (i == 1 ? y : z); }
};

inline Vec3 operator+(Vec3 a, Vec3 b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
inline Vec3 operator-(Vec3 a, Vec3 b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
inline Vec3 operator-(Vec3 a) { return {-a.x, -a.y, -a.z}; }
inline Vec3 operator*(Vec3 a, Vec3 b) { return {a.x * b.x, a.y * b.y, a.z * b.z}; }
inline Vec3 operator*(Vec3 a, float s) { return {a.x * s, a.y * s, a.z * s}; }
inline Vec3 operator*(float s, Vec3 a) { return a * s; }
inline Vec3 operator/(Vec3 a, float s) { return a * (1.f / s); }
inline Vec3& operator+=(Vec3& a, Vec3 b) { return a = a + b; }
inline Vec3& operator*=(Vec3& a, Vec3 b) { return a = a * b; }
inline Vec3& operator*=(Vec3& a, float s) { return a = a * s; }
inline float dot(Vec3 a, Vec3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
inline Vec3 cross(Vec3 a, Vec3 b) { return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x}; }
inline float length(Vec3 a) { return std::sqrt(dot(a, a)); }
inline Vec3 normalize(Vec3 a) {
  const float l = length(a);
  return l > 0.f ? a / l : Vec3(0.f, 0.f, 1.f);
}
inline Vec3 min(Vec3 a, Vec3 b) { return {std::min(a.x, b.x), std::min(a.y, b.y), std::min(a.z, b.z)}; }
inline Vec3 max(Vec3 a, Vec3 b) { return {std::max(a.x, b.x), std::max(a.y, b.y), std::max(a.z, b.z)}; }
inline float maxComponent(Vec3 a) { return std::max(a.x, std::max(a.y, a.z)); }

// Orthonormal basis around a unit normal (Duff et al. 2017, "Building an Orthonormal Basis, Revisited").
inline void orthonormalBasis(Vec3 n, Vec3& t, Vec3& b) {
  const float sign = std::copysign(1.f, n.z);
  const float a = -1.f / (sign + n.z);
  const float c = n.x * n.y * a;
  t = {1.f + sign * n.x * n.x * a, sign * c, -sign * n.x};
  b = {c, sign + n.y * n.y * a, -n.y};
}

struct Quat {
  float x = 0.f, y = 0.f, z = 0.f, w = 1.f;
};

inline Quat normalize(Quat q) {
  const float l = std::sqrt(q.x * q.x + q.y * q.y + q.z * q.z + q.w * q.w);
  return l > 0.f ? Quat{q.x / l, q.y / l, q.z / l, q.w / l} : Quat{};
}

// Shortest-arc spherical interpolation, as glTF animation asks for rotations.
inline Quat slerp(Quat a, Quat b, float s) {
  float d = a.x * b.x + a.y * b.y + a.z * b.z + a.w * b.w;
  if (d < 0.f) b = {-b.x, -b.y, -b.z, -b.w}, d = -d;
  if (d > 0.9995f)
    return normalize(Quat{a.x + s * (b.x - a.x), a.y + s * (b.y - a.y), a.z + s * (b.z - a.z), a.w + s * (b.w - a.w)});
  const float theta = std::acos(d);
  const float wa = std::sin((1.f - s) * theta) / std::sin(theta), wb = std::sin(s * theta) / std::sin(theta);
  return {wa * a.x + wb * b.x, wa * a.y + wb * b.y, wa * a.z + wb * b.z, wa * a.w + wb * b.w};
}

// Column-major: m[column * 4 + row], as glTF stores node matrices.
struct Mat4 {
  std::array<float, 16> m{1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
  float operator()(int row, int column) const { return m[column * 4 + row]; }
  float& operator()(int row, int column) { return m[column * 4 + row]; }
};

inline Mat4 operator*(const Mat4& a, const Mat4& b) {
  Mat4 r;
  for (int row = 0; row < 4; ++row)
    for (int column = 0; column < 4; ++column) {
      float s = 0.f;
      for (int k = 0; k < 4; ++k) s += a(row, k) * b(k, column);
      r(row, column) = s;
    }
  return r;
}

inline Mat4 composeTrs(Vec3 t, Quat q, Vec3 s) {
  q = normalize(q);
  const float xx = q.x * q.x, yy = q.y * q.y, zz = q.z * q.z;
  const float xy = q.x * q.y, xz = q.x * q.z, yz = q.y * q.z, wx = q.w * q.x, wy = q.w * q.y, wz = q.w * q.z;
  Mat4 r;
  r(0, 0) = (1 - 2 * (yy + zz)) * s.x, r(0, 1) = 2 * (xy - wz) * s.y, r(0, 2) = 2 * (xz + wy) * s.z;
  r(1, 0) = 2 * (xy + wz) * s.x, r(1, 1) = (1 - 2 * (xx + zz)) * s.y, r(1, 2) = 2 * (yz - wx) * s.z;
  r(2, 0) = 2 * (xz - wy) * s.x, r(2, 1) = 2 * (yz + wx) * s.y, r(2, 2) = (1 - 2 * (xx + yy)) * s.z;
  r(0, 3) = t.x, r(1, 3) = t.y, r(2, 3) = t.z;
  return r;
}

inline Vec3 transformPoint(const Mat4& a, Vec3 p) {
  return {a(0, 0) * p.x + a(0, 1) * p.y + a(0, 2) * p.z + a(0, 3), a(1, 0) * p.x + a(1, 1) * p.y + a(1, 2) * p.z + a(1, 3),
          a(2, 0) * p.x + a(2, 1) * p.y + a(2, 2) * p.z + a(2, 3)};
}
inline Vec3 transformVector(const Mat4& a, Vec3 v) {
  return {a(0, 0) * v.x + a(0, 1) * v.y + a(0, 2) * v.z, a(1, 0) * v.x + a(1, 1) * v.y + a(1, 2) * v.z,
          a(2, 0) * v.x + a(2, 1) * v.y + a(2, 2) * v.z};
}
// Normals transform with the inverse transpose; the cofactor matrix is that up to a positive or
// negative scale, and normalisation removes the scale (the sign is fixed by the caller's facing test).
inline Vec3 transformNormal(const Mat4& a, Vec3 n) {
  const Vec3 c0{a(0, 0), a(1, 0), a(2, 0)}, c1{a(0, 1), a(1, 1), a(2, 1)}, c2{a(0, 2), a(1, 2), a(2, 2)};
  const Vec3 r0 = cross(c1, c2), r1 = cross(c2, c0), r2 = cross(c0, c1);
  return normalize(r0 * n.x + r1 * n.y + r2 * n.z);
}

}  // namespace obvh::render
