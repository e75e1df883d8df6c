// The SSE4.2 instantiation of the four-wide kernels, in a target region for the reason given in
// wide_traversal_avx2.cpp.
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
#pragma GCC target("sse4.2")

#include "traversal/wide_kernels.h"

namespace obvh {

const WideKernels<4>& bvh4Sse42Kernels(ChildOrder order) {
  return makeWideKernels<simd::Float4Sse, simd::Float4Sse>(order);
}

}  // namespace obvh

#pragma GCC pop_options
