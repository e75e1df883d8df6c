// The AVX2 instantiation of the eight-wide kernels (compiled with -mavx2 and without FMA
// contraction, so every lane rounds exactly like the scalar reference).
#include "simd/float4_sse.h"
#include "simd/float8_avx.h"
#include "traversal/wide_traverse.h"

namespace obvh {

const WideKernels<8>& bvh8Avx2Kernels() { return makeWideKernels<simd::Float8Avx, simd::Float4Sse>(); }

}  // namespace obvh
