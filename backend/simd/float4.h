// Four-lane float vectors behind one interface: Float4Scalar (plain C++, the reference) and
// Float4Sse (SSE intrinsics). Kernels are templates over the vector type, so the same source
// yields the scalar path the tests compare against and the SIMD path.
#pragma once

#include <algorithm>
#include <cstdint>

#if defined(__SSE2__)
#include <emmintrin.h>
#endif

namespace obvh::simd {

struct Float4Scalar {
  float v[4];

  static Float4Scalar broadcast(float x) { return {{x, x, x, x}}; }
  static Float4Scalar load(const float* p) { return {{p[0], p[1], p[2], p[3]}}; }
  float operator[](int i) const { return v[i]; }

  friend Float4Scalar operator-(Float4Scalar a, Float4Scalar b) {
    return {{a.v[0] - b.v[0], a.v[1] - b.v[1], a.v[2] - b.v[2], a.v[3] - b.v[3]}};
  }
  friend Float4Scalar operator*(Float4Scalar a, Float4Scalar b) {
    return {{a.v[0] * b.v[0], a.v[1] * b.v[1], a.v[2] * b.v[2], a.v[3] * b.v[3]}};
  }
  // Same NaN rule as minps/maxps: when either operand is NaN the result is the second operand.
  friend Float4Scalar min(Float4Scalar a, Float4Scalar b) {
    Float4Scalar r;
    for (int i = 0; i < 4; ++i) r.v[i] = a.v[i] < b.v[i] ? a.v[i] : b.v[i];
    return r;
  }
  friend Float4Scalar max(Float4Scalar a, Float4Scalar b) {
    Float4Scalar r;
    for (int i = 0; i < 4; ++i) r.v[i] = a.v[i] > b.v[i] ? a.v[i] : b.v[i];
    return r;
  }
  // Bit i set when a[i] <= b[i] (false for NaN, like the SSE compare).
  friend int lessEqualMask(Float4Scalar a, Float4Scalar b) {
    int m = 0;
    for (int i = 0; i < 4; ++i) m |= (a.v[i] <= b.v[i]) << i;
    return m;
  }
  void store(float* p) const { std::copy(v, v + 4, p); }
};

#if defined(__SSE2__)
struct Float4Sse {
  __m128 v;

  static Float4Sse broadcast(float x) { return {_mm_set1_ps(x)}; }
  static Float4Sse load(const float* p) { return {_mm_load_ps(p)}; }  // p is 16-byte aligned

  friend Float4Sse operator-(Float4Sse a, Float4Sse b) { return {_mm_sub_ps(a.v, b.v)}; }
  friend Float4Sse operator*(Float4Sse a, Float4Sse b) { return {_mm_mul_ps(a.v, b.v)}; }
  // minps/maxps return the second operand when either is NaN; the scalar type above mirrors that.
  friend Float4Sse min(Float4Sse a, Float4Sse b) { return {_mm_min_ps(a.v, b.v)}; }
  friend Float4Sse max(Float4Sse a, Float4Sse b) { return {_mm_max_ps(a.v, b.v)}; }
  friend int lessEqualMask(Float4Sse a, Float4Sse b) { return _mm_movemask_ps(_mm_cmple_ps(a.v, b.v)); }
  void store(float* p) const { _mm_store_ps(p, v); }
};
#endif

}  // namespace obvh::simd
