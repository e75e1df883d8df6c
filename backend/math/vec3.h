// Small 3-vector and axis-aligned box types used by every backend stage.
#pragma once

#include <algorithm>
#include <cmath>
#include <limits>

namespace obvh {

struct Vec3f {
  float x = 0.f, y = 0.f, z = 0.f;

  Vec3f() = default;
  constexpr Vec3f(float x_, float y_, float z_) : x(x_), y(y_), z(z_) {}

  // x, y, z are contiguous in this standard-layout struct; indexing avoids branches in hot loops.
  float operator[](int axis) const { return (&x)[axis]; }
  float& operator[](int axis) { return (&x)[axis]; }
};

inline Vec3f operator+(Vec3f a, Vec3f b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
inline Vec3f operator-(Vec3f a, Vec3f b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
inline Vec3f operator*(Vec3f a, float s) { return {a.x * s, a.y * s, a.z * s}; }
inline Vec3f minv(Vec3f a, Vec3f b) { return {std::min(a.x, b.x), std::min(a.y, b.y), std::min(a.z, b.z)}; }
inline Vec3f maxv(Vec3f a, Vec3f b) { return {std::max(a.x, b.x), std::max(a.y, b.y), std::max(a.z, b.z)}; }
inline float dot(Vec3f a, Vec3f b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
inline Vec3f cross(Vec3f a, Vec3f b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}

struct Box3f {
  Vec3f lower{std::numeric_limits<float>::infinity(), std::numeric_limits<float>::infinity(),
              std::numeric_limits<float>::infinity()};
  Vec3f upper{-std::numeric_limits<float>::infinity(), -std::numeric_limits<float>::infinity(),
              -std::numeric_limits<float>::infinity()};

  void extend(Vec3f p) {
    lower = minv(lower, p);
    upper = maxv(upper, p);
  }
  void extend(const Box3f& b) {
    lower = minv(lower, b.lower);
    upper = maxv(upper, b.upper);
  }
  bool empty() const { return lower.x > upper.x || lower.y > upper.y || lower.z > upper.z; }
  Vec3f center2() const { return lower + upper; }  // twice the centre: avoids a multiply per primitive
  // Half the surface area; SAH only compares ratios, so the factor 2 is dropped.
  float halfArea() const {
    if (empty()) return 0.f;
    const Vec3f d = upper - lower;
    return d.x * d.y + d.y * d.z + d.z * d.x;
  }
  int largestAxis() const {
    const Vec3f d = upper - lower;
    return (d.x >= d.y && d.x >= d.z) ? 0 : (d.y >= d.z ? 1 : 2);
  }
  // The length of the box's longest side; 0 for an empty box.
  float largestSide() const { return empty() ? 0.f : (upper - lower)[largestAxis()]; }
};

}  // namespace obvh
