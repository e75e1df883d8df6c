// Four-lane float vector on SSE intrinsics; mirrors FloatScalar<4> (float_scalar.h).
#pragma once

#include <cstddef>
#include <cstdint>
#include <xmmintrin.h>
#include <emmintrin.h>
#include <smmintrin.h>

namespace obvh::simd {

struct Float4Sse {
  static constexpr int kWidth = 4;
  using Lanes4 = Float4Sse;  // see FloatScalar::Lanes4
  __m128 v;

  static Float4Sse broadcast(float x) { return {_mm_set1_ps(x)}; }
  static Float4Sse load(const float* p) { return {_mm_load_ps(p)}; }  // p is 16-byte aligned
  void store(float* p) const { _mm_store_ps(p, v); }
  // See Float8Avx::fromLanes.
  template <typename LaneValue>
  static Float4Sse fromLanes(LaneValue&& laneValue) {
    return {_mm_setr_ps(laneValue(0), laneValue(1), laneValue(2), laneValue(3))};
  }
  // See FloatScalar::loadColumns.
  static void loadColumns(const float* p, size_t stride, Float4Sse out[4]) {
    __m128 a = _mm_loadu_ps(p), b = _mm_loadu_ps(p + stride), c = _mm_loadu_ps(p + 2 * stride),
           d = _mm_loadu_ps(p + 3 * stride);
    _MM_TRANSPOSE4_PS(a, b, c, d);
    out[0].v = a, out[1].v = b, out[2].v = c, out[3].v = d;
  }
  // See FloatScalar::storeColumns.
  static void storeColumns(const Float4Sse columns[4], float* p, size_t stride) {
    __m128 a = columns[0].v, b = columns[1].v, c = columns[2].v, d = columns[3].v;
    _MM_TRANSPOSE4_PS(a, b, c, d);
    _mm_storeu_ps(p, a), _mm_storeu_ps(p + stride, b), _mm_storeu_ps(p + 2 * stride, c), _mm_storeu_ps(p + 3 * stride, d);
  }
  // See FloatScalar::select.
  friend Float4Sse select(int mask, Float4Sse a, Float4Sse b) {
    const __m128i bits = _mm_setr_epi32(1, 2, 4, 8);
    const __m128 in = _mm_castsi128_ps(_mm_cmpeq_epi32(_mm_and_si128(_mm_set1_epi32(mask), bits), bits));
    return {_mm_or_ps(_mm_and_ps(in, a.v), _mm_andnot_ps(in, b.v))};
  }
  static Float4Sse loadUnaligned(const float* p) { return {_mm_loadu_ps(p)}; }
  // See FloatScalar::loadThree. p[3] must be readable: the four floats are loaded and lane 3 replaced.
  static Float4Sse loadThree(const float* p, float fourth) {
    const __m128 keep = _mm_castsi128_ps(_mm_setr_epi32(-1, -1, -1, 0));
    return {_mm_or_ps(_mm_and_ps(_mm_loadu_ps(p), keep), _mm_setr_ps(0.f, 0.f, 0.f, fourth))};
  }
  void storeUnaligned(float* p) const { _mm_storeu_ps(p, v); }
  // Truncates each lane toward zero, as a float-to-int cast does for values in range.
  void truncate(int* out) const { _mm_storeu_si128(reinterpret_cast<__m128i*>(out), _mm_cvttps_epi32(v)); }

  friend Float4Sse operator+(Float4Sse a, Float4Sse b) { return {_mm_add_ps(a.v, b.v)}; }
  friend Float4Sse operator-(Float4Sse a, Float4Sse b) { return {_mm_sub_ps(a.v, b.v)}; }
  friend Float4Sse operator*(Float4Sse a, Float4Sse b) { return {_mm_mul_ps(a.v, b.v)}; }
  friend Float4Sse operator/(Float4Sse a, Float4Sse b) { return {_mm_div_ps(a.v, b.v)}; }
  friend Float4Sse min(Float4Sse a, Float4Sse b) { return {_mm_min_ps(a.v, b.v)}; }
  friend Float4Sse max(Float4Sse a, Float4Sse b) { return {_mm_max_ps(a.v, b.v)}; }
  friend Float4Sse abs(Float4Sse a) { return {_mm_andnot_ps(_mm_set1_ps(-0.f), a.v)}; }
  // See FloatScalar::replaceNaN.
  friend Float4Sse replaceNaN(Float4Sse a, Float4Sse b) {
    const __m128 nan = _mm_cmpunord_ps(a.v, a.v);
    return {_mm_or_ps(_mm_andnot_ps(nan, a.v), _mm_and_ps(nan, b.v))};
  }
  // See FloatScalar::selectBySign (SSE2: the kernels that use it are baseline code).
  friend Float4Sse selectBySign(Float4Sse sign, Float4Sse ifClear, Float4Sse ifSet) {
    const __m128 set = _mm_castsi128_ps(_mm_srai_epi32(_mm_castps_si128(sign.v), 31));
    return {_mm_or_ps(_mm_andnot_ps(set, ifClear.v), _mm_and_ps(set, ifSet.v))};
  }
  friend int lessEqualMask(Float4Sse a, Float4Sse b) { return _mm_movemask_ps(_mm_cmple_ps(a.v, b.v)); }
  friend int lessMask(Float4Sse a, Float4Sse b) { return _mm_movemask_ps(_mm_cmplt_ps(a.v, b.v)); }
  friend int signMask(Float4Sse a) { return _mm_movemask_ps(a.v); }
  // Lanes whose three values' sign bits are not all the same.
  friend int unequalSignsMask(Float4Sse a, Float4Sse b, Float4Sse c) {
    return _mm_movemask_ps(_mm_or_ps(_mm_xor_ps(a.v, b.v), _mm_xor_ps(a.v, c.v)));
  }
  friend int equalMask(Float4Sse a, Float4Sse b) { return _mm_movemask_ps(_mm_cmpeq_ps(a.v, b.v)); }
  // See FloatScalar::maxOfBits. SSE4.1 instructions: only the SSE4.2 and AVX2 kernels call them.
  __attribute__((target("sse4.1"))) friend Float4Sse maxOfBits(Float4Sse a, Float4Sse b) {
    return {_mm_castsi128_ps(_mm_max_epi32(_mm_castps_si128(a.v), _mm_castps_si128(b.v)))};
  }
  __attribute__((target("sse4.1"))) friend Float4Sse minOfBits(Float4Sse a, Float4Sse b) {
    return {_mm_castsi128_ps(_mm_min_epi32(_mm_castps_si128(a.v), _mm_castps_si128(b.v)))};
  }
  friend Float4Sse bitsPlus(Float4Sse a, int32_t k) {
    return {_mm_castsi128_ps(_mm_add_epi32(_mm_castps_si128(a.v), _mm_set1_epi32(k)))};
  }
  friend Float4Sse bitsPlusLanes(Float4Sse a, Float4Sse b) {
    return {_mm_castsi128_ps(_mm_add_epi32(_mm_castps_si128(a.v), _mm_castps_si128(b.v)))};
  }
  friend int bitsLessEqualMask(Float4Sse a, Float4Sse b) { return ~bitsGreaterMask(a, b) & 15; }
  friend int bitsGreaterMask(Float4Sse a, Float4Sse b) {
    return _mm_movemask_ps(_mm_castsi128_ps(_mm_cmpgt_epi32(_mm_castps_si128(a.v), _mm_castps_si128(b.v))));
  }
  // See FloatScalar::minOfEachRow: rows paired lane by lane, then the pairs' halves.
  static Float4Sse minOfEachRow(const Float4Sse rows[4]) {
    const __m128 r01 = _mm_min_ps(_mm_unpacklo_ps(rows[0].v, rows[1].v), _mm_unpackhi_ps(rows[0].v, rows[1].v));
    const __m128 r23 = _mm_min_ps(_mm_unpacklo_ps(rows[2].v, rows[3].v), _mm_unpackhi_ps(rows[2].v, rows[3].v));
    return {_mm_min_ps(_mm_movelh_ps(r01, r23), _mm_movehl_ps(r23, r01))};
  }
  // See FloatScalar::minOfLanes.
  friend float minOfLanes(Float4Sse a, int mask) {
    const __m128 x = select(mask, a, Float4Sse{_mm_set1_ps(__builtin_inff())}).v;
    const __m128 pairs = _mm_min_ps(x, _mm_movehl_ps(x, x));
    return _mm_cvtss_f32(_mm_min_ss(pairs, _mm_shuffle_ps(pairs, pairs, _MM_SHUFFLE(1, 1, 1, 1))));
  }
};

}  // namespace obvh::simd
