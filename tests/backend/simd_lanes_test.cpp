// The SIMD vector types against their scalar reference, for the operations the kernels use
// outside the lane-by-lane arithmetic the traversal tests already compare.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

#include "simd/cpu_features.h"
#include "simd/float4_sse.h"
#include "simd/float_scalar.h"

namespace obvh {
namespace {

// Each SIMD type is exercised inside one function compiled for its instruction set, so no vector
// value crosses between code of different targets (their calling conventions differ).
float sseMinOfLanes(const float* values, int mask) { return minOfLanes(simd::Float4Sse::load(values), mask); }
void sseFromLanes(const float* values, float* out) {
  simd::Float4Sse::fromLanes([&](int lane) { return values[lane]; }).store(out);
}
void sseLoadColumns(const float* rows, size_t stride, float* out) {
  simd::Float4Sse columns[4];
  simd::Float4Sse::loadColumns(rows, stride, columns);
  for (int c = 0; c < 4; ++c) columns[c].storeUnaligned(out + 4 * c);
}
void sseStoreColumns(const float* columns, float* rows, size_t stride) {
  simd::Float4Sse c[4];
  for (int k = 0; k < 4; ++k) c[k] = simd::Float4Sse::loadUnaligned(columns + 4 * k);
  simd::Float4Sse::storeColumns(c, rows, stride);
}
void sseSelect(int mask, const float* a, const float* b, float* out) {
  select(mask, simd::Float4Sse::loadUnaligned(a), simd::Float4Sse::loadUnaligned(b)).storeUnaligned(out);
}
void sseMinOfEachRow(const float* rows, float* out) {
  simd::Float4Sse r[4];
  for (int i = 0; i < 4; ++i) r[i] = simd::Float4Sse::loadUnaligned(rows + 4 * i);
  simd::Float4Sse::minOfEachRow(r).storeUnaligned(out);
}
void sseSelectBySign(const float* sign, const float* a, const float* b, float* out) {
  selectBySign(simd::Float4Sse::loadUnaligned(sign), simd::Float4Sse::loadUnaligned(a), simd::Float4Sse::loadUnaligned(b))
      .storeUnaligned(out);
}
int sseUnequalSignsMask(const float* a, const float* b, const float* c) {
  return unequalSignsMask(simd::Float4Sse::loadUnaligned(a), simd::Float4Sse::loadUnaligned(b),
                          simd::Float4Sse::loadUnaligned(c));
}

}  // namespace
}  // namespace obvh

#pragma GCC push_options
#pragma GCC target("avx2")
#include "simd/float8_avx.h"
namespace obvh {
namespace {
float avxMinOfLanes(const float* values, int mask) { return minOfLanes(simd::Float8Avx::load(values), mask); }
void avxFromLanes(const float* values, float* out) {
  simd::Float8Avx::fromLanes([&](int lane) { return values[lane]; }).store(out);
}
void avxLoadColumns(const float* rows, size_t stride, float* out) {
  simd::Float8Avx columns[8];
  simd::Float8Avx::loadColumns(rows, stride, columns);
  for (int c = 0; c < 8; ++c) _mm256_storeu_ps(out + 8 * c, columns[c].v);
}
void avxStoreColumns(const float* columns, float* rows, size_t stride) {
  simd::Float8Avx c[8];
  for (int k = 0; k < 8; ++k) c[k].v = _mm256_loadu_ps(columns + 8 * k);
  simd::Float8Avx::storeColumns(c, rows, stride);
}
void avxSelect(int mask, const float* a, const float* b, float* out) {
  _mm256_storeu_ps(out, select(mask, simd::Float8Avx{_mm256_loadu_ps(a)}, simd::Float8Avx{_mm256_loadu_ps(b)}).v);
}
void avxMinOfEachRow(const float* rows, float* out) {
  simd::Float8Avx r[8];
  for (int i = 0; i < 8; ++i) r[i] = simd::Float8Avx{_mm256_loadu_ps(rows + 8 * i)};
  _mm256_storeu_ps(out, simd::Float8Avx::minOfEachRow(r).v);
}
void avxSelectBySign(const float* sign, const float* a, const float* b, float* out) {
  _mm256_storeu_ps(out, selectBySign(simd::Float8Avx{_mm256_loadu_ps(sign)}, simd::Float8Avx{_mm256_loadu_ps(a)},
                                     simd::Float8Avx{_mm256_loadu_ps(b)})
                            .v);
}
int avxUnequalSignsMask(const float* a, const float* b, const float* c) {
  return unequalSignsMask(simd::Float8Avx{_mm256_loadu_ps(a)}, simd::Float8Avx{_mm256_loadu_ps(b)},
                          simd::Float8Avx{_mm256_loadu_ps(c)});
}
}  // namespace
}  // namespace obvh
#pragma GCC pop_options

namespace obvh {
namespace {

// minOfLanes of every mask over random values (ties, repeats and both zeros' signs avoided: the
// kernels only compare the result), including the empty mask (+inf).
template <int N>
void expectMinOfLanesMatchesReference(float (*simdMinOfLanes)(const float*, int)) {
  std::mt19937 rng(11);
  std::uniform_int_distribution<int> pick(1, 9);
  for (int trial = 0; trial < 200; ++trial) {
    alignas(32) float values[N];
    for (float& v : values) v = float(pick(rng)) * (pick(rng) > 5 ? -0.5f : 0.5f);
    const simd::FloatScalar<N> reference = simd::FloatScalar<N>::load(values);
    for (int mask = 0; mask < (1 << N); ++mask)
      ASSERT_EQ(simdMinOfLanes(values, mask), minOfLanes(reference, mask)) << "mask " << mask;
  }
}

TEST(SimdLanes, MinOfLanesMatchesTheScalarReference) {
  expectMinOfLanesMatchesReference<4>(sseMinOfLanes);
  if (simd::cpuHasAvx2()) expectMinOfLanesMatchesReference<8>(avxMinOfLanes);
}

// fromLanes puts lane i's value in lane i, in the SIMD types as in the reference.
template <int N>
void expectFromLanesMatchesReference(void (*simdFromLanes)(const float*, float*)) {
  alignas(32) const float values[8] = {1.f, -2.f, 3.5f, -0.f, std::numeric_limits<float>::infinity(), 6.f, 7.f, -8.f};
  alignas(32) float simd[8] = {}, reference[8] = {};
  simdFromLanes(values, simd);
  simd::FloatScalar<N>::fromLanes([&](int lane) { return values[lane]; }).store(reference);
  for (int lane = 0; lane < N; ++lane) {
    EXPECT_EQ(reference[lane], values[lane]) << "lane " << lane;
    EXPECT_EQ(simd[lane], values[lane]) << "lane " << lane;
    EXPECT_EQ(std::signbit(simd[lane]), std::signbit(values[lane])) << "lane " << lane;
  }
}

TEST(SimdLanes, FromLanesMatchesTheScalarReference) {
  expectFromLanesMatchesReference<4>(sseFromLanes);
  if (simd::cpuHasAvx2()) expectFromLanesMatchesReference<8>(avxFromLanes);
}

// minOfEachRow: lane i the smallest lane of row i, for rows of distinct random values (so a lane
// or row taken from the wrong place fails) with +-inf among them, as the packet set-up's idle lanes
// hold; checked against the reference and against minOfLanes of each row.
template <int N>
void expectMinOfEachRowMatchesReference(void (*simdMinOfEachRow)(const float*, float*)) {
  std::mt19937 rng(23);
  std::uniform_real_distribution<float> value(-100.f, 100.f);
  std::uniform_int_distribution<int> pick(0, 9);
  for (int trial = 0; trial < 500; ++trial) {
    alignas(32) float rows[N * N];
    for (float& v : rows) {
      const int kind = pick(rng);
      v = kind == 0 ? std::numeric_limits<float>::infinity() : kind == 1 ? -std::numeric_limits<float>::infinity() : value(rng);
    }
    alignas(32) float simd[N], reference[N];
    simdMinOfEachRow(rows, simd);
    simd::FloatScalar<N> referenceRows[N];
    for (int i = 0; i < N; ++i) referenceRows[i] = simd::FloatScalar<N>::load(rows + N * i);
    simd::FloatScalar<N>::minOfEachRow(referenceRows).store(reference);
    for (int i = 0; i < N; ++i) {
      ASSERT_EQ(simd[i], reference[i]) << "row " << i << " trial " << trial;
      ASSERT_EQ(reference[i], minOfLanes(referenceRows[i], (1 << N) - 1)) << "row " << i << " trial " << trial;
    }
  }
}

TEST(SimdLanes, MinOfEachRowMatchesTheScalarReference) {
  expectMinOfEachRowMatchesReference<4>(sseMinOfEachRow);
  if (simd::cpuHasAvx2()) expectMinOfEachRowMatchesReference<8>(avxMinOfEachRow);
}

// The reference itself: the smallest of the lanes in the mask only, +inf for none.
TEST(SimdLanes, MinOfLanesIgnoresLanesOutsideTheMask) {
  alignas(16) const float values[4] = {3.f, -1.f, 2.f, -5.f};
  const simd::Float4Scalar v = simd::Float4Scalar::load(values);
  EXPECT_EQ(minOfLanes(v, 0b0000), std::numeric_limits<float>::infinity());
  EXPECT_EQ(minOfLanes(v, 0b0001), 3.f);
  EXPECT_EQ(minOfLanes(v, 0b0101), 2.f);
  EXPECT_EQ(minOfLanes(v, 0b0111), -1.f);
  EXPECT_EQ(minOfLanes(v, 0b1111), -5.f);
  EXPECT_EQ(sseMinOfLanes(values, 0b0101), 2.f);
}

// replaceNaN and division (the oriented wide node test's zero-direction rule), lane by lane.
TEST(SimdLanes, ReplaceNaNAndDivisionMatchTheScalarReference) {
  const float inf = std::numeric_limits<float>::infinity(), nan = std::numeric_limits<float>::quiet_NaN();
  alignas(16) const float numerators[4] = {0.f, -2.f, nan, 3.f};
  alignas(16) const float denominators[4] = {0.f, -0.f, 1.f, inf};
  alignas(16) const float replacements[4] = {7.f, -inf, 8.f, 9.f};
  alignas(16) float sse[4], reference[4];
  replaceNaN(simd::Float4Sse::load(numerators) / simd::Float4Sse::load(denominators),
             simd::Float4Sse::load(replacements)).store(sse);
  replaceNaN(simd::Float4Scalar::load(numerators) / simd::Float4Scalar::load(denominators),
             simd::Float4Scalar::load(replacements)).store(reference);
  const float expected[4] = {7.f, inf, 8.f, 0.f};  // 0/0 and NaN/1 replaced; -2/-0 = +inf; 3/inf = 0
  for (int lane = 0; lane < 4; ++lane) {
    EXPECT_EQ(sse[lane], expected[lane]) << "lane " << lane;
    EXPECT_EQ(reference[lane], expected[lane]) << "lane " << lane;
  }
}

// loadColumns: column c of N rows of a strided array (the leading fields of N structs of `stride`
// floats, as PacketLanes reads its rays), in the SIMD types as in the reference; every value
// distinct, so a swapped lane or column fails.
template <int N>
void expectLoadColumnsMatchesReference(void (*simdLoadColumns)(const float*, size_t, float*)) {
  constexpr size_t kStride = 10;  // a Ray is ten floats
  float rows[N * kStride];
  for (size_t i = 0; i < N * kStride; ++i) rows[i] = float(i) + 0.25f;
  float simd[N * N];
  simdLoadColumns(rows, kStride, simd);
  simd::FloatScalar<N> reference[N];
  simd::FloatScalar<N>::loadColumns(rows, kStride, reference);
  for (int c = 0; c < N; ++c)
    for (int lane = 0; lane < N; ++lane) {
      EXPECT_EQ(reference[c].v[lane], rows[size_t(lane) * kStride + size_t(c)]) << "column " << c << " lane " << lane;
      EXPECT_EQ(simd[c * N + lane], rows[size_t(lane) * kStride + size_t(c)]) << "column " << c << " lane " << lane;
    }
}

TEST(SimdLanes, LoadColumnsMatchesTheScalarReference) {
  expectLoadColumnsMatchesReference<4>(sseLoadColumns);
  if (simd::cpuHasAvx2()) expectLoadColumnsMatchesReference<8>(avxLoadColumns);
}

// storeColumns, the inverse of loadColumns: lane i of column c lands at row i, place c of a strided
// array, and nothing else of the array changes (the places past the N columns of each row keep
// their values), in the SIMD types as in the reference.
template <int N>
void expectStoreColumnsMatchesReference(void (*simdStoreColumns)(const float*, float*, size_t)) {
  constexpr size_t kStride = 10;  // a WatertightRay is ten words
  float columns[N * N];
  for (int i = 0; i < N * N; ++i) columns[i] = float(i) + 0.5f;
  float simd[N * kStride], reference[N * kStride];
  for (size_t i = 0; i < N * kStride; ++i) simd[i] = reference[i] = -float(i);
  simdStoreColumns(columns, simd, kStride);
  simd::FloatScalar<N> c[N];
  for (int k = 0; k < N; ++k) c[k] = simd::FloatScalar<N>::load(columns + N * k);
  simd::FloatScalar<N>::storeColumns(c, reference, kStride);
  for (size_t row = 0; row < N; ++row)
    for (size_t place = 0; place < kStride; ++place) {
      const size_t at = row * kStride + place;
      const float expected = place < N ? columns[place * N + row] : -float(at);
      EXPECT_EQ(reference[at], expected) << "row " << row << " place " << place;
      EXPECT_EQ(simd[at], expected) << "row " << row << " place " << place;
    }
}

TEST(SimdLanes, StoreColumnsMatchesTheScalarReference) {
  expectStoreColumnsMatchesReference<4>(sseStoreColumns);
  if (simd::cpuHasAvx2()) expectStoreColumnsMatchesReference<8>(avxStoreColumns);
}

// select takes a's lane where the mask's bit is set, b's elsewhere, for every mask.
template <int N>
void expectSelectMatchesReference(void (*simdSelect)(int, const float*, const float*, float*)) {
  float a[N], b[N];
  for (int lane = 0; lane < N; ++lane) a[lane] = float(lane + 1), b[lane] = -float(lane + 1);
  for (int mask = 0; mask < (1 << N); ++mask) {
    float simd[N], reference[N];
    simdSelect(mask, a, b, simd);
    select(mask, simd::FloatScalar<N>::load(a), simd::FloatScalar<N>::load(b)).store(reference);
    for (int lane = 0; lane < N; ++lane) {
      const float expected = (mask >> lane) & 1 ? a[lane] : b[lane];
      ASSERT_EQ(reference[lane], expected) << "mask " << mask << " lane " << lane;
      ASSERT_EQ(simd[lane], expected) << "mask " << mask << " lane " << lane;
    }
  }
}

TEST(SimdLanes, SelectMatchesTheScalarReference) {
  expectSelectMatchesReference<4>(sseSelect);
  if (simd::cpuHasAvx2()) expectSelectMatchesReference<8>(avxSelect);
}

// selectBySign picks by the sign bit alone (the oriented node test's entry and exit planes by the
// sign of 1/dir): -0 and a NaN with its sign bit set pick the second value, +0, +inf and a NaN
// without it the first.
template <int N>
void expectSelectBySignMatchesReference(void (*simdSelectBySign)(const float*, const float*, const float*, float*)) {
  const float inf = std::numeric_limits<float>::infinity(), nan = std::numeric_limits<float>::quiet_NaN();
  const float signs[8] = {1.f, -1.f, 0.f, -0.f, inf, -inf, nan, -nan};
  for (int offset = 0; offset < 8; offset += N) {
    float sign[N], a[N], b[N], simd[N], reference[N];
    for (int lane = 0; lane < N; ++lane)
      sign[lane] = signs[offset + lane], a[lane] = float(lane + 1), b[lane] = -float(lane + 1);
    simdSelectBySign(sign, a, b, simd);
    selectBySign(simd::FloatScalar<N>::load(sign), simd::FloatScalar<N>::load(a), simd::FloatScalar<N>::load(b))
        .store(reference);
    for (int lane = 0; lane < N; ++lane) {
      const float expected = std::signbit(sign[lane]) ? b[lane] : a[lane];
      EXPECT_EQ(reference[lane], expected) << "sign " << sign[lane];
      EXPECT_EQ(simd[lane], expected) << "sign " << sign[lane];
    }
  }
}

TEST(SimdLanes, SelectBySignMatchesTheScalarReference) {
  expectSelectBySignMatchesReference<4>(sseSelectBySign);
  if (simd::cpuHasAvx2()) expectSelectBySignMatchesReference<8>(avxSelectBySign);
}

// unequalSignsMask compares sign bits alone (the block test's edge functions, whose zero lanes are
// judged apart): every triple of values from a set with both zeros, both infinities and NaNs of
// both signs, lane by lane.
template <int N>
void expectUnequalSignsMaskMatchesReference(int (*simdUnequalSignsMask)(const float*, const float*, const float*)) {
  const float inf = std::numeric_limits<float>::infinity(), nan = std::numeric_limits<float>::quiet_NaN();
  const float values[8] = {2.f, -3.f, 0.f, -0.f, inf, -inf, nan, -nan};
  float a[N], b[N], c[N];
  int lane = 0, triples = 0;
  const auto check = [&] {
    int expected = 0;
    for (int k = 0; k < lane; ++k)
      expected |= int(std::signbit(a[k]) != std::signbit(b[k]) || std::signbit(a[k]) != std::signbit(c[k])) << k;
    for (int k = lane; k < N; ++k) a[k] = b[k] = c[k] = 1.f;
    EXPECT_EQ(simdUnequalSignsMask(a, b, c), expected);
    EXPECT_EQ(unequalSignsMask(simd::FloatScalar<N>::load(a), simd::FloatScalar<N>::load(b),
                               simd::FloatScalar<N>::load(c)),
              expected);
    lane = 0;
  };
  for (float x : values)
    for (float y : values)
      for (float z : values) {
        a[lane] = x, b[lane] = y, c[lane] = z;
        ++triples;
        if (++lane == N) check();
      }
  if (lane) check();
  EXPECT_EQ(triples, 512);
}

TEST(SimdLanes, UnequalSignsMaskMatchesTheScalarReference) {
  expectUnequalSignsMaskMatchesReference<4>(sseUnequalSignsMask);
  if (simd::cpuHasAvx2()) expectUnequalSignsMaskMatchesReference<8>(avxUnequalSignsMask);
}

}  // namespace
}  // namespace obvh
