// Four-lane float vector on SSE intrinsics; mirrors FloatScalar<4> (float_scalar.h).
#pragma once

#include <emmintrin.h>

namespace obvh::simd {

struct Float4Sse {
  static constexpr int kWidth = 4;
  __m128 v;

  static Float4Sse broadcast(float x) { return {_mm_set1_ps(x)}; }
  static Float4Sse load(const float* p) { return {_mm_load_ps(p)}; }  // p is 16-byte aligned
  void store(float* p) const { _mm_store_ps(p, v); }

  friend Float4Sse operator+(Float4Sse a, Float4Sse b) { return {_mm_add_ps(a.v, b.v)}; }
  friend Float4Sse operator-(Float4Sse a, Float4Sse b) { return {_mm_sub_ps(a.v, b.v)}; }
  friend Float4Sse operator*(Float4Sse a, Float4Sse b) { return {_mm_mul_ps(a.v, b.v)}; }
  friend Float4Sse min(Float4Sse a, Float4Sse b) { return {_mm_min_ps(a.v, b.v)}; }
  friend Float4Sse max(Float4Sse a, Float4Sse b) { return {_mm_max_ps(a.v, b.v)}; }
  friend int lessEqualMask(Float4Sse a, Float4Sse b) { return _mm_movemask_ps(_mm_cmple_ps(a.v, b.v)); }
  friend int lessMask(Float4Sse a, Float4Sse b) { return _mm_movemask_ps(_mm_cmplt_ps(a.v, b.v)); }
  friend int equalMask(Float4Sse a, Float4Sse b) { return _mm_movemask_ps(_mm_cmpeq_ps(a.v, b.v)); }
};

}  // namespace obvh::simd
