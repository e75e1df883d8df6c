// N-lane float vectors in plain C++: the reference the SIMD types (float4_sse.h, float8_avx.h)
// mirror operation by operation, so the same kernel template yields the scalar path the tests
// compare against. NaN rules follow the x86 instructions.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <limits>

namespace obvh::simd {

template <int N>
struct FloatScalar {
  static constexpr int kWidth = N;
  // The four-lane type the kernels of this width use for per-ray set-up (the scalar reference's).
  using Lanes4 = FloatScalar<4>;
  float v[N];

  static FloatScalar broadcast(float x) {
    FloatScalar r;
    std::fill(r.v, r.v + N, x);
    return r;
  }
  static FloatScalar load(const float* p) {
    FloatScalar r;
    std::copy(p, p + N, r.v);
    return r;
  }
  void store(float* p) const { std::copy(v, v + N, p); }
  // Lanes 0-2 from p, lane 3 `fourth` (four lanes only).
  static FloatScalar loadThree(const float* p, float fourth) {
    static_assert(N == 4);
    return {{p[0], p[1], p[2], fourth}};
  }
  template <typename LaneValue>
  static FloatScalar fromLanes(LaneValue&& laneValue) {
    FloatScalar r;
    for (int i = 0; i < N; ++i) r.v[i] = laneValue(i);
    return r;
  }

  // Eight lanes as two halves of four: lanes 0-3 `low`, 4-7 `high` (halves), lanes i and i + 4 both
  // p[i] (twice), and the halves stored apart (storeHalves): two rays against one block of four
  // triangles in one pass.
  static FloatScalar halves(float low, float high) {
    static_assert(N == 8);
    return {{low, low, low, low, high, high, high, high}};
  }
  static FloatScalar twice(const float* p) {
    static_assert(N == 8);
    return {{p[0], p[1], p[2], p[3], p[0], p[1], p[2], p[3]}};
  }
  void storeHalves(float* low, float* high) const {
    static_assert(N == 8);
    std::copy(v, v + 4, low);
    std::copy(v + 4, v + 8, high);
  }
  // Column c < N of the N rows of N floats that start at p, p + stride, ...: out[c] lane i is
  // p[i * stride + c] (a transposed load, as of the leading fields of N structs).
  static void loadColumns(const float* p, size_t stride, FloatScalar out[N]) {
    for (int c = 0; c < N; ++c)
      for (int i = 0; i < N; ++i) out[c].v[i] = p[size_t(i) * stride + size_t(c)];
  }
  // The inverse of loadColumns: p[i * stride + c] = columns[c] lane i (a transposed store, as of the
  // leading fields of N structs).
  static void storeColumns(const FloatScalar columns[N], float* p, size_t stride) {
    for (int c = 0; c < N; ++c)
      for (int i = 0; i < N; ++i) p[size_t(i) * stride + size_t(c)] = columns[c].v[i];
  }
  // Lane i of a where bit i of mask is set, else b's.
  friend FloatScalar select(int mask, FloatScalar a, FloatScalar b) {
    FloatScalar r;
    for (int i = 0; i < N; ++i) r.v[i] = (mask >> i) & 1 ? a.v[i] : b.v[i];
    return r;
  }

  template <typename Op>
  static FloatScalar map(const FloatScalar& a, const FloatScalar& b, Op op) {
    FloatScalar r;
    for (int i = 0; i < N; ++i) r.v[i] = op(a.v[i], b.v[i]);
    return r;
  }
  template <typename Cmp>
  static int maskOf(const FloatScalar& a, const FloatScalar& b, Cmp cmp) {
    int m = 0;
    for (int i = 0; i < N; ++i) m |= int(cmp(a.v[i], b.v[i])) << i;
    return m;
  }

  friend FloatScalar operator+(FloatScalar a, FloatScalar b) { return map(a, b, [](float x, float y) { return x + y; }); }
  friend FloatScalar operator-(FloatScalar a, FloatScalar b) { return map(a, b, [](float x, float y) { return x - y; }); }
  friend FloatScalar operator*(FloatScalar a, FloatScalar b) { return map(a, b, [](float x, float y) { return x * y; }); }
  friend FloatScalar operator/(FloatScalar a, FloatScalar b) { return map(a, b, [](float x, float y) { return x / y; }); }
  // minps/maxps return the second operand when either is NaN.
  friend FloatScalar min(FloatScalar a, FloatScalar b) { return map(a, b, [](float x, float y) { return x < y ? x : y; }); }
  friend FloatScalar max(FloatScalar a, FloatScalar b) { return map(a, b, [](float x, float y) { return x > y ? x : y; }); }
  // |a| lane by lane: the sign bit cleared (NaNs stay NaNs).
  friend FloatScalar abs(FloatScalar a) { return map(a, a, [](float x, float) { return std::fabs(x); }); }
  // a, with its NaN lanes replaced by replacement's.
  friend FloatScalar replaceNaN(FloatScalar a, FloatScalar b) {
    return map(a, b, [](float x, float y) { return x != x ? y : x; });
  }
  // Lane i of ifSet where lane i of sign has its sign bit set (negative numbers, -0, NaNs with the
  // bit), else of ifClear, as blendvps picks.
  friend FloatScalar selectBySign(FloatScalar sign, FloatScalar ifClear, FloatScalar ifSet) {
    FloatScalar r;
    for (int i = 0; i < N; ++i) r.v[i] = std::signbit(sign.v[i]) ? ifSet.v[i] : ifClear.v[i];
    return r;
  }
  // Bit i set when the comparison holds in lane i (false for NaN, like the ordered SSE compares).
  friend int lessEqualMask(FloatScalar a, FloatScalar b) { return maskOf(a, b, [](float x, float y) { return x <= y; }); }
  friend int lessMask(FloatScalar a, FloatScalar b) { return maskOf(a, b, [](float x, float y) { return x < y; }); }
  // Lane i's sign bit as bit i (NaNs and zeros included), as movmskps gives it.
  friend int signMask(FloatScalar a) {
    int m = 0;
    for (int i = 0; i < N; ++i) m |= int(std::signbit(a.v[i])) << i;
    return m;
  }
  friend int unequalSignsMask(FloatScalar a, FloatScalar b, FloatScalar c) {
    int m = 0;
    for (int i = 0; i < N; ++i) {
      const bool sign = std::signbit(a.v[i]);
      m |= int(std::signbit(b.v[i]) != sign || std::signbit(c.v[i]) != sign) << i;
    }
    return m;
  }
  friend int equalMask(FloatScalar a, FloatScalar b) { return maskOf(a, b, [](float x, float y) { return x == y; }); }
  // The lanes' bit patterns as signed integers: ordered as the floats are among non-negative floats,
  // and every negative float (or -0, or NaN with the sign bit) below them. A box test whose entry
  // distances include a non-negative tnear can therefore take its maximum and minimum with integer
  // instructions (one cycle each, where float min/max take four).
  static int32_t bitsOf(float x) {
    int32_t i;
    std::memcpy(&i, &x, sizeof i);
    return i;
  }
  static float floatOf(int32_t i) {
    float x;
    std::memcpy(&x, &i, sizeof x);
    return x;
  }
  friend FloatScalar maxOfBits(FloatScalar a, FloatScalar b) {
    return map(a, b, [](float x, float y) { return bitsOf(x) > bitsOf(y) ? x : y; });
  }
  friend FloatScalar minOfBits(FloatScalar a, FloatScalar b) {
    return map(a, b, [](float x, float y) { return bitsOf(x) < bitsOf(y) ? x : y; });
  }
  // Adds k to each lane's bit pattern: k ulps up for a non-negative float, toward zero for a
  // negative one (wrapping as the SIMD integer add does).
  friend FloatScalar bitsPlus(FloatScalar a, int32_t k) {
    FloatScalar r;
    for (int i = 0; i < N; ++i) r.v[i] = floatOf(int32_t(uint32_t(bitsOf(a.v[i])) + uint32_t(k)));
    return r;
  }
  // Lane by lane, b's bits added to a's (wrapping as the SIMD integer add does).
  friend FloatScalar bitsPlusLanes(FloatScalar a, FloatScalar b) {
    FloatScalar r;
    for (int i = 0; i < N; ++i) r.v[i] = floatOf(int32_t(uint32_t(bitsOf(a.v[i])) + uint32_t(bitsOf(b.v[i]))));
    return r;
  }
  friend int bitsLessEqualMask(FloatScalar a, FloatScalar b) {
    return maskOf(a, b, [](float x, float y) { return bitsOf(x) <= bitsOf(y); });
  }
  friend int bitsGreaterMask(FloatScalar a, FloatScalar b) {
    return maskOf(a, b, [](float x, float y) { return bitsOf(x) > bitsOf(y); });
  }
  // Lane i the smallest lane of rows[i], for N rows at once (a reduction of N vectors into one, as
  // a transposition would pair them up); the rows must hold no NaN (the SIMD versions may then
  // differ only in the sign of a zero).
  static FloatScalar minOfEachRow(const FloatScalar rows[N]) {
    FloatScalar r;
    for (int i = 0; i < N; ++i) r.v[i] = *std::min_element(rows[i].v, rows[i].v + N);
    return r;
  }
  // The smallest of the lanes whose bit is set in mask, +inf when none is; those lanes must not be
  // NaN (the SIMD versions may then differ only in the sign of a zero).
  friend float minOfLanes(FloatScalar a, int mask) {
    float m = std::numeric_limits<float>::infinity();
    for (int i = 0; i < N; ++i)
      if ((mask >> i) & 1) m = a.v[i] < m ? a.v[i] : m;
    return m;
  }
};

using Float4Scalar = FloatScalar<4>;
using Float8Scalar = FloatScalar<8>;

}  // namespace obvh::simd
