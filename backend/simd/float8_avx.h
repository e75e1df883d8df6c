// Eight-lane float vector on AVX intrinsics; mirrors FloatScalar<8> (float_scalar.h). Only the
// AVX2 kernel file includes it; every function carries the AVX2 target itself.
#pragma once

#include <immintrin.h>

#include <cstddef>
#include <cstdint>

#include "simd/float4_sse.h"

#define OBVH_AVX2 __attribute__((target("avx2")))

namespace obvh::simd {

struct Float8Avx {
  static constexpr int kWidth = 8;
  using Lanes4 = Float4Sse;  // see FloatScalar::Lanes4
  __m256 v;

  OBVH_AVX2 static Float8Avx broadcast(float x) { return {_mm256_set1_ps(x)}; }
  OBVH_AVX2 static Float8Avx load(const float* p) { return {_mm256_load_ps(p)}; }  // p is 32-byte aligned
  OBVH_AVX2 void store(float* p) const { _mm256_store_ps(p, v); }
  // See FloatScalar::halves, twice and storeHalves (p, low and high 16-byte aligned).
  OBVH_AVX2 static Float8Avx halves(float low, float high) {
    return {_mm256_insertf128_ps(_mm256_castps128_ps256(_mm_set1_ps(low)), _mm_set1_ps(high), 1)};
  }
  OBVH_AVX2 static Float8Avx twice(const float* p) { return {_mm256_broadcast_ps(reinterpret_cast<const __m128*>(p))}; }
  OBVH_AVX2 void storeHalves(float* low, float* high) const {
    _mm_store_ps(low, _mm256_castps256_ps128(v));
    _mm_store_ps(high, _mm256_extractf128_ps(v, 1));
  }
  // Lane i is laneValue(i), assembled in registers: values just written one by one and loaded as a
  // vector would wait for the stores to retire (a store-forwarding stall).
  template <typename LaneValue>
  OBVH_AVX2 static Float8Avx fromLanes(LaneValue&& laneValue) {
    return {_mm256_setr_ps(laneValue(0), laneValue(1), laneValue(2), laneValue(3), laneValue(4), laneValue(5),
                           laneValue(6), laneValue(7))};
  }

  OBVH_AVX2 friend Float8Avx operator+(Float8Avx a, Float8Avx b) { return {_mm256_add_ps(a.v, b.v)}; }
  OBVH_AVX2 friend Float8Avx operator-(Float8Avx a, Float8Avx b) { return {_mm256_sub_ps(a.v, b.v)}; }
  OBVH_AVX2 friend Float8Avx operator*(Float8Avx a, Float8Avx b) { return {_mm256_mul_ps(a.v, b.v)}; }
  OBVH_AVX2 friend Float8Avx operator/(Float8Avx a, Float8Avx b) { return {_mm256_div_ps(a.v, b.v)}; }
  // See FloatScalar::replaceNaN.
  OBVH_AVX2 friend Float8Avx replaceNaN(Float8Avx a, Float8Avx b) {
    return {_mm256_blendv_ps(a.v, b.v, _mm256_cmp_ps(a.v, a.v, _CMP_UNORD_Q))};
  }
  // See FloatScalar::selectBySign.
  OBVH_AVX2 friend Float8Avx selectBySign(Float8Avx sign, Float8Avx ifClear, Float8Avx ifSet) {
    return {_mm256_blendv_ps(ifClear.v, ifSet.v, sign.v)};
  }
  OBVH_AVX2 friend Float8Avx min(Float8Avx a, Float8Avx b) { return {_mm256_min_ps(a.v, b.v)}; }
  OBVH_AVX2 friend Float8Avx max(Float8Avx a, Float8Avx b) { return {_mm256_max_ps(a.v, b.v)}; }
  OBVH_AVX2 friend int lessEqualMask(Float8Avx a, Float8Avx b) { return _mm256_movemask_ps(_mm256_cmp_ps(a.v, b.v, _CMP_LE_OQ)); }
  OBVH_AVX2 friend int lessMask(Float8Avx a, Float8Avx b) { return _mm256_movemask_ps(_mm256_cmp_ps(a.v, b.v, _CMP_LT_OQ)); }
  OBVH_AVX2 friend int equalMask(Float8Avx a, Float8Avx b) { return _mm256_movemask_ps(_mm256_cmp_ps(a.v, b.v, _CMP_EQ_OQ)); }
  OBVH_AVX2 friend Float8Avx abs(Float8Avx a) { return {_mm256_andnot_ps(_mm256_set1_ps(-0.f), a.v)}; }
  OBVH_AVX2 friend int signMask(Float8Avx a) { return _mm256_movemask_ps(a.v); }
  OBVH_AVX2 friend int unequalSignsMask(Float8Avx a, Float8Avx b, Float8Avx c) {
    return _mm256_movemask_ps(_mm256_or_ps(_mm256_xor_ps(a.v, b.v), _mm256_xor_ps(a.v, c.v)));
  }
  // See FloatScalar::maxOfBits.
  OBVH_AVX2 friend Float8Avx maxOfBits(Float8Avx a, Float8Avx b) {
    return {_mm256_castsi256_ps(_mm256_max_epi32(_mm256_castps_si256(a.v), _mm256_castps_si256(b.v)))};
  }
  OBVH_AVX2 friend Float8Avx minOfBits(Float8Avx a, Float8Avx b) {
    return {_mm256_castsi256_ps(_mm256_min_epi32(_mm256_castps_si256(a.v), _mm256_castps_si256(b.v)))};
  }
  OBVH_AVX2 friend Float8Avx bitsPlus(Float8Avx a, int32_t k) {
    return {_mm256_castsi256_ps(_mm256_add_epi32(_mm256_castps_si256(a.v), _mm256_set1_epi32(k)))};
  }
  OBVH_AVX2 friend Float8Avx bitsPlusLanes(Float8Avx a, Float8Avx b) {
    return {_mm256_castsi256_ps(_mm256_add_epi32(_mm256_castps_si256(a.v), _mm256_castps_si256(b.v)))};
  }
  OBVH_AVX2 friend int bitsLessEqualMask(Float8Avx a, Float8Avx b) {
    return ~bitsGreaterMask(a, b) & 255;
  }
  OBVH_AVX2 friend int bitsGreaterMask(Float8Avx a, Float8Avx b) {
    return _mm256_movemask_ps(_mm256_castsi256_ps(_mm256_cmpgt_epi32(_mm256_castps_si256(a.v), _mm256_castps_si256(b.v))));
  }
  // Lane i of the result is lane slots[i] of table (slots: eight indices 0..7, 32-byte aligned).
  OBVH_AVX2 friend Float8Avx lanesAt(Float8Avx table, const int32_t* slots) {
    return {_mm256_permutevar8x32_ps(table.v, _mm256_load_si256(reinterpret_cast<const __m256i*>(slots)))};
  }
  // See FloatScalar::loadColumns: eight rows, interleaved in pairs, then in fours, then halves
  // exchanged.
  OBVH_AVX2 static void loadColumns(const float* p, size_t stride, Float8Avx out[8]) {
    const float* rows[8];
    for (int i = 0; i < 8; ++i) rows[i] = p + size_t(i) * stride;
    loadColumnsOf(rows, out);
  }
  // loadColumns of eight rows anywhere (row i at rows[i]): out[c] lane i is rows[i][c].
  OBVH_AVX2 static void loadColumnsOf(const float* const rows[8], Float8Avx out[8]) {
    __m256 row[8];
    for (int i = 0; i < 8; ++i) row[i] = _mm256_loadu_ps(rows[i]);
    transpose(row);
    for (int c = 0; c < 8; ++c) out[c].v = row[c];
  }
  // See FloatScalar::storeColumns: the transpose of loadColumns, and so the same exchanges.
  OBVH_AVX2 static void storeColumns(const Float8Avx columns[8], float* p, size_t stride) {
    __m256 row[8];
    for (int c = 0; c < 8; ++c) row[c] = columns[c].v;
    transpose(row);
    for (int i = 0; i < 8; ++i) _mm256_storeu_ps(p + size_t(i) * stride, row[i]);
  }
  // An 8x8 matrix in eight vectors, transposed: interleaved in pairs, then in fours, then halves
  // exchanged.
  OBVH_AVX2 static void transpose(__m256 m[8]) {
    __m256 pairs[8], fours[8];
    for (int i = 0; i < 8; i += 2) {
      pairs[i] = _mm256_unpacklo_ps(m[i], m[i + 1]);      // columns 0, 1 | 4, 5 of rows i, i + 1
      pairs[i + 1] = _mm256_unpackhi_ps(m[i], m[i + 1]);  // columns 2, 3 | 6, 7
    }
    for (int i = 0; i < 8; i += 4) {
      fours[i] = _mm256_shuffle_ps(pairs[i], pairs[i + 2], _MM_SHUFFLE(1, 0, 1, 0));      // column 0 | 4
      fours[i + 1] = _mm256_shuffle_ps(pairs[i], pairs[i + 2], _MM_SHUFFLE(3, 2, 3, 2));  // column 1 | 5
      fours[i + 2] = _mm256_shuffle_ps(pairs[i + 1], pairs[i + 3], _MM_SHUFFLE(1, 0, 1, 0));  // 2 | 6
      fours[i + 3] = _mm256_shuffle_ps(pairs[i + 1], pairs[i + 3], _MM_SHUFFLE(3, 2, 3, 2));  // 3 | 7
    }
    for (int c = 0; c < 4; ++c) {
      m[c] = _mm256_permute2f128_ps(fours[c], fours[c + 4], 0x20);
      m[c + 4] = _mm256_permute2f128_ps(fours[c], fours[c + 4], 0x31);
    }
  }
  // See FloatScalar::select.
  OBVH_AVX2 friend Float8Avx select(int mask, Float8Avx a, Float8Avx b) {
    const __m256i bits = _mm256_setr_epi32(1, 2, 4, 8, 16, 32, 64, 128);
    const __m256i in = _mm256_cmpeq_epi32(_mm256_and_si256(_mm256_set1_epi32(mask), bits), bits);
    return {_mm256_blendv_ps(b.v, a.v, _mm256_castsi256_ps(in))};
  }
  // See FloatScalar::minOfEachRow: as Float4Sse's within each 128-bit half, then the halves'
  // results of rows 0-3 and 4-7 exchanged and combined.
  OBVH_AVX2 static Float8Avx minOfEachRow(const Float8Avx rows[8]) {
    __m256 pairs[4];
    for (int i = 0; i < 4; ++i)
      pairs[i] = _mm256_min_ps(_mm256_unpacklo_ps(rows[2 * i].v, rows[2 * i + 1].v),
                               _mm256_unpackhi_ps(rows[2 * i].v, rows[2 * i + 1].v));
    const __m256 low = _mm256_min_ps(_mm256_shuffle_ps(pairs[0], pairs[1], _MM_SHUFFLE(1, 0, 1, 0)),
                                     _mm256_shuffle_ps(pairs[0], pairs[1], _MM_SHUFFLE(3, 2, 3, 2)));
    const __m256 high = _mm256_min_ps(_mm256_shuffle_ps(pairs[2], pairs[3], _MM_SHUFFLE(1, 0, 1, 0)),
                                      _mm256_shuffle_ps(pairs[2], pairs[3], _MM_SHUFFLE(3, 2, 3, 2)));
    return {_mm256_min_ps(_mm256_permute2f128_ps(low, high, 0x20), _mm256_permute2f128_ps(low, high, 0x31))};
  }
  // See FloatScalar::minOfLanes.
  OBVH_AVX2 friend float minOfLanes(Float8Avx a, int mask) {
    const __m256 x = select(mask, a, Float8Avx{_mm256_set1_ps(__builtin_inff())}).v;
    const __m128 halves = _mm_min_ps(_mm256_castps256_ps128(x), _mm256_extractf128_ps(x, 1));
    const __m128 pairs = _mm_min_ps(halves, _mm_movehl_ps(halves, halves));
    return _mm_cvtss_f32(_mm_min_ss(pairs, _mm_shuffle_ps(pairs, pairs, _MM_SHUFFLE(1, 1, 1, 1))));
  }
};

}  // namespace obvh::simd

#undef OBVH_AVX2
