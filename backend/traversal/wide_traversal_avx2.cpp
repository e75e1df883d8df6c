// The AVX2 instantiation of the eight-wide kernels.
//
// Only this file's own code is compiled for AVX2 (a target region, not a -mavx2 flag for the whole
// file): the inline functions of the shared headers, included first, stay baseline x86-64 code, so
// whichever copy of them the linker keeps runs on every CPU; the run-time check picks this file's
// kernels only on CPUs with AVX2. No FMA contraction (-ffp-contract=off): every lane rounds like
// the scalar reference.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <optional>

#include "simd/double_lanes.h"
#include "simd/float4_sse.h"
#include "traversal/box_test.h"
#include "traversal/triangle_block_leaf.h"
#include "traversal/wide_traversal.h"

#pragma GCC push_options
#pragma GCC target("avx2")

#include "simd/double4_avx.h"
#include "simd/float8_avx.h"
#include "traversal/wide_kernels.h"

namespace obvh {

const WideKernels<8>& bvh8Avx2Kernels(ChildOrder order) {
  return makeWideKernels<simd::Float8Avx, simd::Float4Sse>(order);
}

}  // namespace obvh

#pragma GCC pop_options
