// Eight-lane float vector on AVX intrinsics; mirrors FloatScalar<8> (float_scalar.h). Only the
// AVX2 kernel file includes it; every function carries the AVX2 target itself.
#pragma once

#include <immintrin.h>

#define OBVH_AVX2 __attribute__((target("avx2")))

namespace obvh::simd {

struct Float8Avx {
  static constexpr int kWidth = 8;
  __m256 v;

  OBVH_AVX2 static Float8Avx broadcast(float x) { return {_mm256_set1_ps(x)}; }
  OBVH_AVX2 static Float8Avx load(const float* p) { return {_mm256_load_ps(p)}; }  // p is 32-byte aligned
  OBVH_AVX2 void store(float* p) const { _mm256_store_ps(p, v); }

  OBVH_AVX2 friend Float8Avx operator+(Float8Avx a, Float8Avx b) { return {_mm256_add_ps(a.v, b.v)}; }
  OBVH_AVX2 friend Float8Avx operator-(Float8Avx a, Float8Avx b) { return {_mm256_sub_ps(a.v, b.v)}; }
  OBVH_AVX2 friend Float8Avx operator*(Float8Avx a, Float8Avx b) { return {_mm256_mul_ps(a.v, b.v)}; }
  OBVH_AVX2 friend Float8Avx min(Float8Avx a, Float8Avx b) { return {_mm256_min_ps(a.v, b.v)}; }
  OBVH_AVX2 friend Float8Avx max(Float8Avx a, Float8Avx b) { return {_mm256_max_ps(a.v, b.v)}; }
  OBVH_AVX2 friend int lessEqualMask(Float8Avx a, Float8Avx b) { return _mm256_movemask_ps(_mm256_cmp_ps(a.v, b.v, _CMP_LE_OQ)); }
  OBVH_AVX2 friend int lessMask(Float8Avx a, Float8Avx b) { return _mm256_movemask_ps(_mm256_cmp_ps(a.v, b.v, _CMP_LT_OQ)); }
  OBVH_AVX2 friend int equalMask(Float8Avx a, Float8Avx b) { return _mm256_movemask_ps(_mm256_cmp_ps(a.v, b.v, _CMP_EQ_OQ)); }
};

}  // namespace obvh::simd

#undef OBVH_AVX2
