// The four-lane double type that goes with a kernel's node vector type FN, that is with its
// instruction set: DoubleLanesOf<FN>::type. Double4Avx's specialization is in double4_avx.h.
#pragma once

#include "simd/double4_sse.h"
#include "simd/double_scalar.h"

namespace obvh::simd {

template <typename FN>
struct DoubleLanesOf;

template <int N>
struct FloatScalar;
template <int N>
struct DoubleLanesOf<FloatScalar<N>> {
  using type = Double4Scalar;
};

struct Float4Sse;
template <>
struct DoubleLanesOf<Float4Sse> {
  using type = Double4Sse;
};

template <typename FN>
using DoubleLanes = typename DoubleLanesOf<FN>::type;

}  // namespace obvh::simd
