// The SSE instantiation of the four-wide kernels (compiled with -msse4.2).
#include "simd/float4_sse.h"
#include "traversal/wide_traverse.h"

namespace obvh {

const WideKernels<4>& bvh4Sse42Kernels() { return makeWideKernels<simd::Float4Sse, simd::Float4Sse>(); }

}  // namespace obvh
