// Four lanes of double in one AVX register; mirrors Double4Scalar (double_scalar.h). Only the AVX2
// kernel files include it; every function carries the AVX2 target itself.
#pragma once

#include <immintrin.h>

#include "simd/double_lanes.h"

#define OBVH_AVX2 __attribute__((target("avx2")))

namespace obvh::simd {

struct Double4Avx {
  __m256d v;

  OBVH_AVX2 static Double4Avx broadcast(double x) { return {_mm256_set1_pd(x)}; }
  OBVH_AVX2 static Double4Avx widen(const float* p) { return {_mm256_cvtps_pd(_mm_load_ps(p))}; }  // 16-byte aligned
  OBVH_AVX2 void narrow(float* p) const { _mm_store_ps(p, _mm256_cvtpd_ps(v)); }

  OBVH_AVX2 friend Double4Avx operator+(Double4Avx a, Double4Avx b) { return {_mm256_add_pd(a.v, b.v)}; }
  OBVH_AVX2 friend Double4Avx operator-(Double4Avx a, Double4Avx b) { return {_mm256_sub_pd(a.v, b.v)}; }
  OBVH_AVX2 friend Double4Avx operator*(Double4Avx a, Double4Avx b) { return {_mm256_mul_pd(a.v, b.v)}; }
  OBVH_AVX2 friend Double4Avx operator/(Double4Avx a, Double4Avx b) { return {_mm256_div_pd(a.v, b.v)}; }
  OBVH_AVX2 friend int zeroMask(Double4Avx a) {
    return _mm256_movemask_pd(_mm256_cmp_pd(a.v, _mm256_setzero_pd(), _CMP_EQ_OQ));
  }
};

struct Float8Avx;
template <>
struct DoubleLanesOf<Float8Avx> {
  using type = Double4Avx;
};

}  // namespace obvh::simd

#undef OBVH_AVX2
