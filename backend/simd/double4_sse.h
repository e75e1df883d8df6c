// Four lanes of double as two SSE2 registers; mirrors Double4Scalar (double_scalar.h).
#pragma once

#include <emmintrin.h>

namespace obvh::simd {

struct Double4Sse {
  __m128d lo, hi;

  static Double4Sse broadcast(double x) { return {_mm_set1_pd(x), _mm_set1_pd(x)}; }
  static Double4Sse widen(const float* p) {  // p is 16-byte aligned
    const __m128 f = _mm_load_ps(p);
    return {_mm_cvtps_pd(f), _mm_cvtps_pd(_mm_movehl_ps(f, f))};
  }
  void narrow(float* p) const { _mm_store_ps(p, _mm_movelh_ps(_mm_cvtpd_ps(lo), _mm_cvtpd_ps(hi))); }

  friend Double4Sse operator+(Double4Sse a, Double4Sse b) { return {_mm_add_pd(a.lo, b.lo), _mm_add_pd(a.hi, b.hi)}; }
  friend Double4Sse operator-(Double4Sse a, Double4Sse b) { return {_mm_sub_pd(a.lo, b.lo), _mm_sub_pd(a.hi, b.hi)}; }
  friend Double4Sse operator*(Double4Sse a, Double4Sse b) { return {_mm_mul_pd(a.lo, b.lo), _mm_mul_pd(a.hi, b.hi)}; }
  friend Double4Sse operator/(Double4Sse a, Double4Sse b) { return {_mm_div_pd(a.lo, b.lo), _mm_div_pd(a.hi, b.hi)}; }
  friend int zeroMask(Double4Sse a) {
    const __m128d zero = _mm_setzero_pd();
    return _mm_movemask_pd(_mm_cmpeq_pd(a.lo, zero)) | (_mm_movemask_pd(_mm_cmpeq_pd(a.hi, zero)) << 2);
  }
};

}  // namespace obvh::simd
