// The scalar reference instantiations of the wide kernels.
#include "simd/float_scalar.h"
#include "traversal/wide_kernels.h"

namespace obvh {

const WideKernels<4>& bvh4ScalarKernels(ChildOrder order) {
  return makeWideKernels<simd::Float4Scalar, simd::Float4Scalar>(order);
}
const WideKernels<8>& bvh8ScalarKernels(ChildOrder order) {
  return makeWideKernels<simd::Float8Scalar, simd::Float4Scalar>(order);
}

}  // namespace obvh
